// The runner: the one path from a validated table request to what it delivers. It opens (or is
// given) the backend, checks what the backend can do before any slow work, reads the inputs (the
// environment), bakes with progress reported per step and a stop honoured at each step, then
// delivers the result: written to a file, handed back as the file's bytes, or kept in memory; and
// it says what the user must see: the delivered error bound (what the file records) and the
// warnings (what was changed on the way to the file). The command line, the server, the Python
// package and jobs all run tables through it (docs/ARCHITECTURE.md, "The data flow"), so that a
// table, its bound and its warnings are the same whoever asked for it.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "brdfbake/tables.hpp"

namespace brdfbake {

// Where a result goes.
enum class TableDelivery {
  Memory,  // nothing is written: the result alone (Python's lut(...) without output=, a preview)
  File,    // written to the request's output, atomically ("-": a table as CSV on standard output)
  Bytes,   // written to a private scratch folder, read back and removed: the files' bytes (the server)
};

// One file of a Bytes delivery.
struct DeliveredFile {
  std::string name;  // relative to the output's folder: the output's file name, or a sidecar's
  std::string bytes;
};

// What delivering a result gave.
struct Delivery {
  TableDelivery to = TableDelivery::Memory;
  // What writing stored (File and Bytes): the encoding, its error, the clamping, the warnings.
  WriteReport report;
  // The bound on |delivered value - converged value|: for a file, what the file records (the
  // integration bound plus the storage error); in memory, the result's own. Empty where the
  // family measures none.
  std::optional<double> error_bound;
  // The bound as files record it (error_bound_text: rounded up, never below); "" without one.
  std::string error_bound_text;
  // What was changed on the way to the file (e.g. clamp_f16), naming the output as the request
  // does (never a scratch path).
  std::vector<std::string> warnings;
  std::vector<DeliveredFile> files;  // Bytes: the output first, then any sidecar, by name
};

// How a front end runs a table. Everything has a default: run_table(request) bakes on the
// request's device and writes the request's output.
struct TableRunOptions {
  TableDelivery delivery = TableDelivery::File;

  // The backend: borrowed (the caller keeps it alive and busy with nothing else), else made by
  // `open_backend` from the request's device, else Backend::open.
  Backend* backend = nullptr;
  std::function<std::shared_ptr<Backend>(const std::string& selector)> open_backend;

  // What the bake reads. inputs.environment: an environment the caller loaded (never freed by the
  // run unless inputs.release_environment does it); when empty and the kind reads one, the run
  // loads request.environment with `load` and frees its pixels as soon as the bake has its cube.
  BakeInputs inputs;
  EnvLoadOptions load;
  // Called once the run has loaded the environment, before the bake (the command line prints what
  // sanitizing replaced there).
  std::function<void(const EnvImage&)> on_environment;

  // Progress of the bake: the fraction done (0..1) and a short label of the step, on the calling
  // thread. A stop is honoured at each step: brdfbake/cancel.hpp's request_cancel, and
  // `stop_requested` when it returns true (one run's stop: the server's abandoned requests, a
  // preview superseded by the next); either throws Cancelled.
  BakeProgress progress;
  std::function<bool()> stop_requested;

  // File delivery: check before any slow work that the output can be written (the nearest folder
  // takes a file); and a folder output (a cube written as images) locked for the run, with the
  // temporaries of killed runs removed (docs/RELIABILITY.md, "Outputs").
  bool check_output = true;
  // The output may be a FIFO, a device or standard output as a file (CSV tables, eval: the outputs
  // that stream; docs/RELIABILITY.md, "Special files"); other outputs refuse them.
  bool output_may_stream = false;
  bool lock_folder_output = false;
  bool wait_for_lock = false;
  std::function<void(long pid)> on_wait;
  // File delivery of a kind that streams (eval) with no pairs in memory: the input is read and the
  // output written chunk by chunk (eval_stream), in constant memory; the result holds no values.
  bool stream = false;

  // Bytes delivery: where the scratch folder goes ("" = the system's temporary folder).
  std::string scratch_dir;
};

// What a run gave.
struct TableRun {
  BakeResult result;
  Delivery delivery;
  // Everything the user should see, in order: the inputs' (an environment sanitized) then the
  // delivery's.
  std::vector<std::string> warnings;
  // Wall time of each step, in seconds: reading the inputs (the environment), the bake
  // (result.seconds), the delivery (encoding, writing, reading back).
  double input_seconds = 0.0, bake_seconds = 0.0, deliver_seconds = 0.0;
};

// Runs a validated request (validate_table) as `options` say. Throws what validation, the backend,
// the inputs and the writers throw (Error naming the field, the file or the option that fixes it;
// ClError; NotAvailableError), Cancelled on a stop; nothing is left behind on a failure.
TableRun run_table(const TableRequest& request, const TableRunOptions& options = {});

// Delivers a result already baked (Python's Result.save, a job's second output of one bake) to
// request.output, as run_table does.
Delivery deliver_result(const BakeResult& result, const TableRequest& request, TableDelivery to,
                        const std::string& scratch_dir = {});

// "environment 'NAME' sanitized: replaced 2 NaN, 0 infinite and 1 negative values" for an
// environment that sanitizing changed, else "" (the warning runs and jobs record).
std::string sanitized_warning(const std::string& environment, const EnvImage& image);

}  // namespace brdfbake
