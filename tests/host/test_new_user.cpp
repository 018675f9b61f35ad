// What a new user stumbled on (issue 24, "A new user's stumbles"), each as a class:
// - option names: every parameter is the option --NAME of its job field (with - for _) on every
//   command, shorter spellings are aliases listed in --help, and an unknown option on any command
//   says which known one is closest.
// - progress: 100 % of a step means its files are written (the writing has its share, an engine's
//   file set is a step of its own).
// - engine files: with --target every file the bake writes is listed in its summary, the plan says
//   the target, and `view` shows each of them.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "brdfbake/error.hpp"
#include "brdfbake/job.hpp"
#include "brdfbake/params.hpp"
#include "brdfbake/plan.hpp"
#include "brdfbake/tables.hpp"
#include "brdfbake/view.hpp"
#include "support/cli_runner.hpp"
#include "support/temp_dir.hpp"

namespace brdfbake {
namespace {

namespace fs = std::filesystem;
using test::CliRun;
using test::run_cli;

// A fresh, empty folder `name` in the test's temporary folder (removed when the test ends).
fs::path temp_dir(const std::string& name) { return brdfbake::test::test_temp_dir(name); }

// Help text with its line wrapping undone: runs of white space as one space.
std::string unwrapped(const std::string& text) {
  std::string s;
  for (char c : text)
    if (!std::isspace(static_cast<unsigned char>(c)))
      s += c;
    else if (!s.empty() && s.back() != ' ')
      s += ' ';
  return s;
}

std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// ---- Option names ----------------------------------------------------------------------------------

// The job's spelling is the option (sh_order is --sh-order, cube_size --cube-size, environment
// --environment); the short spellings of before still work, as aliases, and give the same file.
TEST(OptionNames, TheJobsSpellingIsTheOptionAndShortOnesAreAliases) {
  const fs::path dir = temp_dir("spelling");
  const std::string common = " --source-size 8 --quiet -o ";
  const CliRun job_names =
      run_cli("irradiance --environment builtin:sun --sh-order 5 --cube-size 4" + common + (dir / "a.ktx2").string());
  ASSERT_EQ(job_names.code, 0) << job_names.err;
  const CliRun aliases = run_cli("irradiance --env builtin:sun --sh 5 --cube 4" + common + (dir / "b.ktx2").string());
  ASSERT_EQ(aliases.code, 0) << aliases.err;
  EXPECT_EQ(read_bytes(dir / "a.ktx2"), read_bytes(dir / "b.ktx2"));
  // bake: the same spellings (its sh_order is the table's).
  const CliRun plan = run_cli("bake --environment builtin:sun --sh-order 5 --dry-run --json");
  ASSERT_EQ(plan.code, 0) << plan.err;
  EXPECT_NE(plan.out.find("\"sh_order\": 5"), std::string::npos) << plan.out;
  EXPECT_NE(plan.out.find("\"environment\": \"builtin:sun\""), std::string::npos) << plan.out;
  // Messages name the option by its one spelling.
  const CliRun bad = run_cli("irradiance --sh 4 -o " + (dir / "c.json").string());
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("--sh-order: must be 3 or 5"), std::string::npos) << bad.err;
}

// Every parameter of every kind is its command's option --NAME (a flag on by default --no-NAME),
// and every alias is listed in the command's --help as one.
TEST(OptionNames, EveryParameterIsItsJobNameAndEveryAliasIsListed) {
  for (TableKind k : table_kinds()) {
    const std::string command = table_kind_command(k);
    const CliRun run = run_cli(command + " --help");
    ASSERT_EQ(run.code, 0) << command;
    const std::string help = unwrapped(run.out);
    for (const ParamDef& d : table_schema(k)) {
      SCOPED_TRACE(command + " " + d.name);
      std::string option = d.name;
      std::replace(option.begin(), option.end(), '_', '-');
      EXPECT_EQ(d.cli_name(), option);
      const bool negated = d.type == ParamType::Flag && d.fallback && std::get<bool>(*d.fallback);
      if (option.size() == 1)  // one letter: -n (cxxopts' short form; --n is taken too)
        EXPECT_NE(help.find(" -" + option + " arg"), std::string::npos) << help;
      else
        EXPECT_NE(help.find("--" + std::string(negated ? "no-" : "") + option + " "), std::string::npos) << help;
      for (const std::string& a : d.aliases) EXPECT_NE(help.find("(alias: --" + a + ")"), std::string::npos) << help;
    }
  }
  for (const ParamDef& d : bake_option_schema()) {
    if (d.name == "precision" || d.name == "device") continue;  // the options every command shares
    std::string option = d.name;
    std::replace(option.begin(), option.end(), '_', '-');
    EXPECT_EQ(d.cli_name(), option) << d.name;
  }
  for (const char* command : {"irradiance", "prefilter", "bake"}) {
    const std::string help = unwrapped(run_cli(std::string(command) + " --help").out);
    EXPECT_NE(help.find("--environment arg"), std::string::npos) << help;
    EXPECT_NE(help.find("(alias: --env)"), std::string::npos) << help;
  }
  const std::string bake = unwrapped(run_cli("bake --help").out);
  EXPECT_NE(bake.find("--sh-order arg"), std::string::npos) << bake;
  EXPECT_NE(bake.find("(alias: --sh)"), std::string::npos) << bake;
}

// An unknown option on any command: exit 2, one line, and the closest known option.
TEST(OptionNames, UnknownOptionsOnEveryCommandSayWhatWasMeant) {
  struct Case {
    const char* command;
    const char* typed;
    const char* meant;
  };
  const Case cases[] = {
      {"bake", "--cube-sze 64", "--cube-size"},
      {"run", "--dry-rn x.json", "--dry-run"},
      {"serve", "--max-queu 3", "--max-queue"},
      {"devices", "--jsn", "--json"},
      {"kinds", "--markdwn", "--markdown"},
      {"lut", "--sise 8", "--size"},
      {"fresnel", "--materal gold", "--material"},
      {"thin-film", "--film-iorr 1.3", "--film-ior"},
      {"prefilter", "--distribtion ggx", "--distribution"},
      {"irradiance", "--sh_order 5", "--sh-order"},
      {"eval", "--materal m.json", "--material"},
      {"tabulate", "--layot merl", "--layout"},
      {"view", "--exposur 2 x.ktx2 -o s.png", "--exposure"},
      {"report", "--kindss ggx", "--kinds"},
      {"bake", "--enviroment x.hdr", "--environment"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(std::string(c.command) + " " + c.typed);
    const CliRun r = run_cli(std::string(c.command) + " " + c.typed);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(std::string("did you mean ") + c.meant + "?"), std::string::npos) << r.err;
  }
  // Several options start with what was typed: all of them; nothing close: the pointer to --help.
  const CliRun prefix = run_cli("bake --cube 64");
  EXPECT_NE(prefix.err.find("did you mean --cube-size or --cube-format?"), std::string::npos) << prefix.err;
  const CliRun far = run_cli("lut --zzzzzz 3");
  EXPECT_EQ(far.code, 2);
  EXPECT_NE(far.err.find("unknown option '--zzzzzz' (see --help)"), std::string::npos) << far.err;
}

// No option's help states its default twice: a description that says "default: ..." in words is
// not followed by cxxopts' own "(default: VALUE)" (serve --max-memory printed "default: half the
// machine's (default: 0)").
TEST(OptionNames, NoHelpStatesADefaultTwice) {
  for (const char* command : {"bake", "run", "serve", "devices", "kinds", "lut", "fresnel", "thin-film", "prefilter",
                              "irradiance", "eval", "tabulate", "view", "report"}) {
    const CliRun r = run_cli(std::string(command) + " --help");
    ASSERT_EQ(r.code, 0) << command;
    const std::string help = unwrapped(r.out);
    for (size_t at = help.find("default: "); at != std::string::npos; at = help.find("default: ", at + 1)) {
      // The rest of this option's description: up to the next option ("--" after a space).
      const size_t next = help.find(" --", at);
      const std::string rest = help.substr(at + 9, next == std::string::npos ? std::string::npos : next - at - 9);
      EXPECT_EQ(rest.find("default: "), std::string::npos) << command << ": ..." << help.substr(at, 160);
    }
  }
}

// ---- Engine files ----------------------------------------------------------------------------------

// Every file of the folder (manifest.json aside), relative to it.
std::vector<std::string> files_in(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file() && e.path().filename() != "manifest.json")
      out.push_back(e.path().lexically_relative(dir).string());
  std::sort(out.begin(), out.end());
  return out;
}

// Each target's bake: the plan names the target, the summary lists every file written (a glTF's
// faces as one line with their count), and view shows every file, engine files included.
TEST(EngineFiles, EveryTargetsFilesAreListedAndViewable) {
  const fs::path dir = temp_dir("targets");
  for (const char* target : {"filament", "gltf", "babylon", "khronos-viewer"}) {
    SCOPED_TRACE(target);
    const fs::path out = dir / target;
    const std::string args = std::string("bake --environment builtin:sun --target ") + target +
                             " --cube-size 16 --min-size " + (std::string(target) == "babylon" ? "1" : "4") +
                             " --lut-size 16 --fresnel-size 16 -o " + out.string();
    const CliRun plan = run_cli(args + " --dry-run");
    ASSERT_EQ(plan.code, 0) << plan.err;
    EXPECT_NE(plan.out.find(std::string("target ") + target), std::string::npos) << plan.out;
    EXPECT_EQ(plan.out.find("target generic"), std::string::npos) << plan.out;
    const CliRun baked = run_cli(args);
    ASSERT_EQ(baked.code, 0) << baked.err;
    const std::vector<std::string> written = files_in(out);
    size_t pngs = 0;
    for (const std::string& f : written) {
      if (f.size() > 4 && f.substr(f.size() - 4) == ".png" && std::string(target) == "gltf") {
        ++pngs;  // one line for all of them, with the first and last named
        continue;
      }
      EXPECT_NE(baked.out.find("  " + f + " "), std::string::npos) << f << " is not in the summary:\n" << baked.out;
    }
    if (std::string(target) == "gltf") {
      EXPECT_GE(pngs, 6u);
      EXPECT_NE(baked.out.find(std::to_string(pngs) + " PNGs: "), std::string::npos) << baked.out;
    }
    // view: each file alone (the engine files by their own readers), then the folder.
    for (const std::string& f : written) {
      if (f.size() > 5 && f.substr(f.size() - 5) == ".json" &&
          std::find(written.begin(), written.end(), f.substr(0, f.size() - 5)) != written.end())
        continue;  // a sidecar stands for its file
      const std::string kind = view_kind((out / f).string());
      EXPECT_FALSE(kind.empty()) << f;
    }
    const ContactSheet sheet = render_contact_sheet({out.string()});
    for (const std::string& f : written) {
      if (f.size() > 5 && f.substr(f.size() - 5) == ".json") continue;
      if (std::string(target) == "gltf" && f.size() > 4 && f.substr(f.size() - 4) == ".png")
        continue;  // drawn by its .gltf
      EXPECT_NE(std::find(sheet.files.begin(), sheet.files.end(), (out / f).string()), sheet.files.end())
          << f << " is not on the folder's sheet";
    }
  }
}

// A job's engine_name names the engine's files; it is a file name, never a path.
TEST(EngineFiles, EngineNameIsAFileName) {
  const std::string head = R"({"brdfbake_job": 1, "target": "gltf", "tables": [], "engine_name": )";
  EXPECT_EQ(parse_job(head + R"("sky"})", "job.json").engine_name, "sky");
  for (const char* bad : {R"("../sky")", R"("a/b")", R"("")", R"("..")", "3"}) {
    SCOPED_TRACE(bad);
    try {
      parse_job(head + bad + "}", "job.json");
      ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("job.json: engine_name: "), std::string::npos) << e.what();
    }
  }
}

// ---- Progress ------------------------------------------------------------------------------------

// A job's progress reached 100 % and stayed there while the files were written (seconds, with an
// engine's file set). Now each step's 100 % is its last event, each output has its "writing" event
// below 100 %, and the engine's file set is the last step.
TEST(Progress, HundredPercentMeansTheFilesAreWritten) {
  const fs::path dir = temp_dir("progress");
  Job job = parse_job(R"({"brdfbake_job": 1, "target": "babylon", "environment": "builtin:sun", "tables": [
      {"kind": "ggx", "size": 8, "output": "a.exr"},
      {"kind": "ggx", "size": 8, "output": "b.csv"},
      {"kind": "prefilter", "size": 16, "min_size": 1, "schedule": "babylon", "output": "p.ktx2"},
      {"kind": "irradiance", "output": "sh.json"}]})",
                      "job.json");
  job.output_dir = (dir / "out").string();
  std::vector<JobEvent> events;
  const Manifest m = run_job(job, [&](const JobEvent& e) { events.push_back(e); });
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(m.bakes, 3) << "a.exr and b.csv are one bake";
  const int steps = 3 + 1;  // the distinct tables, then the .env
  std::map<int, bool> done;
  std::set<std::string> writing;
  for (const JobEvent& e : events) {
    SCOPED_TRACE(e.what);
    EXPECT_EQ(e.bakes, steps);
    EXPECT_FALSE(done[e.bake]) << "an event after its step's 100 %";
    if (e.fraction >= 1.0) done[e.bake] = true;
    const size_t at = e.what.find(": writing ");
    if (at != std::string::npos) {
      EXPECT_LT(e.fraction, 1.0);
      writing.insert(e.what.substr(at + 10));
    }
  }
  EXPECT_EQ(writing, (std::set<std::string>{"a.exr", "b.csv", "p.ktx2", "sh.json"}));
  for (int k = 0; k < steps; ++k) EXPECT_TRUE(done[k]) << "step " << k << " never reached 100 %";
  EXPECT_EQ(events.back().bake, steps - 1);
  EXPECT_EQ(events.back().what, "writing the babylon files");
  EXPECT_EQ(events.back().fraction, 1.0);
  EXPECT_TRUE(fs::exists(dir / "out" / "out.env"));
}

}  // namespace
}  // namespace brdfbake
