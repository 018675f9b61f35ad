// brdfbake: the command-line tool. The only place that prints errors and chooses exit codes
// (docs/RELIABILITY.md, "What each failure returns").
#include <time.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <new>
#include <string>
#include <vector>

#include "brdfbake/cancel.hpp"
#include "brdfbake/device.hpp"
#include "brdfbake/diagnostics.hpp"
#include "brdfbake/tables.hpp"
#include "brdfbake/version.hpp"
#include "cli_table.hpp"

namespace {

// SIGINT, SIGTERM and SIGHUP (the terminal closed) ask the run to stop at its next check (between
// device launches, tables, stream chunks and the reads of a file); what it was writing, its lock and
// its staging folder are removed as the Cancelled exception unwinds, and it exits 128 + the signal.
// A second stop signal more than half a second after the first ends the process at once (the next
// run into that folder removes what it left); one within half a second is the same request
// delivered twice (`timeout` sends its signal to the command and to its process group) and is
// ignored. No SA_RESTART, so that a read blocked on standard input returns. SIGPIPE (the reader of
// standard output, standard error or a FIFO went away) stops the run the same way, however often it
// comes: the write that met it fails with EPIPE, and the run ends with 141. `serve` takes its own
// signals (cmd_serve.cpp): SIGHUP and SIGPIPE are left to it.
volatile std::sig_atomic_t g_first_stop_ms = 0;  // when the first stop signal came (monotonic ms, low bits)

long monotonic_ms() {  // async-signal-safe (clock_gettime)
  timespec t{};
  ::clock_gettime(CLOCK_MONOTONIC, &t);
  return static_cast<long>(t.tv_sec % 1000000) * 1000 + t.tv_nsec / 1000000;
}

extern "C" void on_stop_signal(int signal) {
  if (signal == SIGPIPE) {
    if (!brdfbake::cancel_requested()) brdfbake::request_cancel(signal);
    return;
  }
  if (!brdfbake::cancel_requested()) {
    g_first_stop_ms = static_cast<std::sig_atomic_t>(monotonic_ms());
    brdfbake::request_cancel(signal);
    return;
  }
  if (monotonic_ms() - static_cast<long>(g_first_stop_ms) < 500) return;  // the same request again
  ::signal(signal, SIG_DFL);                                              // a second request: end now
  ::raise(signal);
}

void install_stop_handlers(bool all) {
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = 0;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  if (!all) return;
  sigaction(SIGHUP, &action, nullptr);
  sigaction(SIGPIPE, &action, nullptr);
}

// Once a stop signal arrived, whatever failed after it (a read it interrupted, a write to the pipe
// that closed) ends as the stop: 128 + the signal, with the stop's one line (0: no stop requested).
int stopped(const std::string& command) {
  const int signal = brdfbake::cancel_signal();
  if (signal <= 0) return 0;
  try {
    brdfbake::throw_if_cancelled();
  } catch (const brdfbake::Cancelled& e) {
    std::cerr << "brdfbake " << command << ": " << brdfbake::cli::one_line(e.what()) << "\n";
  }
  return 128 + signal;
}

void usage(std::ostream& out) {
  out << "brdfbake " << brdfbake::kVersion << ": physically based BRDF tables on OpenCL devices\n\n"
      << "usage: brdfbake <command> [options]    (brdfbake <command> --help for its options)\n\n"
      << "commands:\n"
      << "  bake      read a glTF scene and bake the tables its materials call for (the main job)\n"
      << "  run       run a job file (JSON: the tables to bake, with every parameter)\n"
      << "  serve     serve the job API over HTTP: warm devices, a persistent queue (docs/SERVICE.md)\n"
      << "  devices   list OpenCL platforms and devices\n"
      << "  kinds     every table kind with its parameters (the job format's reference)\n";
  for (const auto& c : brdfbake::table_commands())  // one per family, from the registry
    out << "  " << c.name << std::string(c.name.size() < 10 ? 10 - c.name.size() : 1, ' ') << c.usage << "\n";
  out << "  view      draw outputs (cubes, tables, SH, MERL, a bake's folder) into one contact sheet PNG\n"
      << "  report    measure accuracy against time on a device: an HTML page of plots and a JSON\n\n"
      << "Every command also takes --verbose: one line per OpenCL program built or loaded from the cache,\n"
      << "with the compiler's build log (which is otherwise never shown unless a build fails), and\n"
      << "--kernel-shape auto|cpu|gpu: the kernels' work shape (default: BRDFBAKE_KERNEL_SHAPE, else auto:\n"
      << "the device's type; docs/DEVICES.md, \"Kernel shapes\").\n";
}

// The OpenCL compiler's output stays off stderr (brdfbake/diagnostics.hpp). --verbose shows every
// build with its log; otherwise a first run on a terminal says once that it is compiling, since a
// cold cache costs about a second a program.
void observe_program_builds(bool verbose, bool quiet) {
  using namespace brdfbake;
  if (verbose) {
    set_program_build_observers({}, [](const ProgramBuild& b) {
      std::fprintf(stderr, "brdfbake: %s %s for %s in %.2f s%s%s\n", b.from_cache ? "loaded" : "built",
                   b.program.c_str(), b.device.c_str(), b.seconds, b.log.empty() ? "" : ":\n", b.log.c_str());
    });
  } else if (!quiet && ::isatty(2)) {
    set_program_build_observers(
        [](const std::string&, const std::string& device) {
          static bool said = false;
          if (said) return;
          said = true;
          std::fprintf(stderr,
                       "brdfbake: compiling OpenCL kernels for %s (first run: about a second a program; "
                       "cached afterwards)\n",
                       device.c_str());
        },
        {});
  }
}

int run(int argc, char** argv) {
  using namespace brdfbake;
  if (argc < 2) {
    usage(std::cerr);
    return cli::kExitUsage;
  }
  const std::string command = argv[1];
  install_stop_handlers(command != "serve");
  // --verbose and --kernel-shape are taken by every command: they are removed here before the
  // command parses its options.
  std::vector<char*> args;
  bool verbose = false, quiet = false;
  std::string kernel_shape;
  for (int i = 0; i < argc; ++i) {
    if (i > 1 && std::strcmp(argv[i], "--verbose") == 0) {
      verbose = true;
      continue;
    }
    if (i > 1 && std::strncmp(argv[i], "--kernel-shape=", 15) == 0) {
      kernel_shape = argv[i] + 15;
      if (kernel_shape.empty()) kernel_shape = " ";  // refused below, as an empty name
      continue;
    }
    if (i > 1 && std::strcmp(argv[i], "--kernel-shape") == 0) {
      if (i + 1 >= argc) {
        std::cerr << "brdfbake " << command << ": --kernel-shape needs a value (auto, cpu or gpu)\n";
        return cli::kExitUsage;
      }
      kernel_shape = argv[++i];
      if (kernel_shape.empty()) kernel_shape = " ";
      continue;
    }
    if (i > 1 && std::strcmp(argv[i], "--quiet") == 0) quiet = true;
    args.push_back(argv[i]);
  }
  args.push_back(nullptr);
  argc = static_cast<int>(args.size()) - 1;
  argv = args.data();
  if (!kernel_shape.empty()) {
    try {
      set_kernel_shape(kernel_shape);
    } catch (const Error& e) {
      std::cerr << "brdfbake " << command << ": --kernel-shape: " << brdfbake::cli::one_line(e.what()) << "\n";
      return cli::kExitUsage;
    }
  }
  observe_program_builds(verbose, quiet);
  // A kernel cache folder that cannot be written: said, and the run goes on without it.
  set_runtime_warning_observer([](const std::string& w) {
    std::fprintf(stderr, "brdfbake: warning: %s\n", brdfbake::cli::one_line(w).c_str());
  });
  try {
    if (command == "devices") return cli::cmd_devices(argc - 1, argv + 1);
    if (command == "fresnel") return cli::cmd_fresnel(argc - 1, argv + 1);
    if (command == "kinds") return cli::cmd_kinds(argc - 1, argv + 1);
    if (const cli::TableCommand* c = cli::table_command(command)) return cli::run_table_command(*c, argc - 1, argv + 1);
    if (command == "bake") return cli::cmd_bake(argc - 1, argv + 1);
    if (command == "run") return cli::cmd_run(argc - 1, argv + 1);
    if (command == "view") return cli::cmd_view(argc - 1, argv + 1);
    if (command == "report") return cli::cmd_report(argc - 1, argv + 1);
    if (command == "serve") return cli::cmd_serve(argc - 1, argv + 1);
    if (command == "--help" || command == "-h" || command == "help") {
      usage(std::cout);
      return 0;
    }
    if (command == "--version") {
      std::cout << "brdfbake " << kVersion << "\n";
      return 0;
    }
    std::cerr << "brdfbake: unknown command '" << brdfbake::cli::one_line(command) << "' (see brdfbake --help)\n";
    return cli::kExitUsage;
  } catch (const cli::UsageError& e) {
    if (const int code = stopped(command)) return code;
    std::cerr << "brdfbake " << command << ": " << brdfbake::cli::one_line(e.what()) << "\n";
    return cli::kExitUsage;
  } catch (const Cancelled& e) {
    std::cerr << "brdfbake " << command << ": " << brdfbake::cli::one_line(e.what()) << "\n";
    return e.signal() > 0 ? 128 + e.signal() : cli::kExitFailure;  // 130 for SIGINT, 143 for SIGTERM
  } catch (const RuntimeFailure& e) {  // I/O, OpenCL, a locked output, a result that is not finite
    if (const int code = stopped(command)) return code;
    std::cerr << "brdfbake " << command << ": " << brdfbake::cli::one_line(e.what()) << "\n";
    return cli::kExitFailure;
  } catch (const Error& e) {  // bad input
    if (const int code = stopped(command)) return code;
    std::cerr << "brdfbake " << command << ": " << brdfbake::cli::one_line(e.what()) << "\n";
    return cli::kExitUsage;
  } catch (const std::bad_alloc&) {
    std::cerr << "brdfbake " << command << ": out of memory\n";
    return cli::kExitFailure;
  } catch (const std::exception& e) {
    if (const int code = stopped(command)) return code;
    std::cerr << "brdfbake " << command << ": " << brdfbake::cli::one_line(e.what()) << "\n";
    return cli::kExitFailure;
  }
}

}  // namespace

// Every output is complete (committed or removed) when run returns: the process ends without
// tearing down the OpenCL implementation (cli_common.hpp; not in BRDFBAKE_ASAN builds).
int main(int argc, char** argv) {
  int code = run(argc, argv);
  // What it printed met a closed pipe (`brdfbake kinds | head -1`): the shell's convention, 141.
  if (code == 0 && brdfbake::cancel_signal() == SIGPIPE) code = 128 + SIGPIPE;
#ifndef BRDFBAKE_ASAN
  std::cout.flush();
  std::cerr.flush();
  if (std::fflush(nullptr) == 0) ::_exit(code);
#endif
  return code;
}
