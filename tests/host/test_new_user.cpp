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

// The job's spelling is the option (sh_order is --sh-order, irradiance_size --irradiance-size,
// environment --environment); the short and old spellings still work, as aliases, and give the same
// file.
TEST(OptionNames, TheJobsSpellingIsTheOptionAndShortOnesAreAliases) {
  const fs::path dir = temp_dir("spelling");
  const std::string common = " --source-size 8 --quiet -o ";
  const CliRun job_names = run_cli("irradiance --environment builtin:sun --sh-order 5 --irradiance-size 4" + common +
                                   (dir / "a.ktx2").string());
  ASSERT_EQ(job_names.code, 0) << job_names.err;
  const CliRun aliases = run_cli("irradiance --env builtin:sun --sh 5 --cube 4" + common + (dir / "b.ktx2").string());
  ASSERT_EQ(aliases.code, 0) << aliases.err;
  EXPECT_EQ(read_bytes(dir / "a.ktx2"), read_bytes(dir / "b.ktx2"));
  const CliRun old_name =
      run_cli("irradiance --env builtin:sun --sh 5 --cube-size 4" + common + (dir / "c.ktx2").string());
  ASSERT_EQ(old_name.code, 0) << old_name.err;
  EXPECT_EQ(read_bytes(dir / "a.ktx2"), read_bytes(dir / "c.ktx2"));
  // bake: the same spellings (its sh_order is the table's).
  const CliRun plan = run_cli("bake --environment builtin:sun --sh-order 5 --dry-run --json");
  ASSERT_EQ(plan.code, 0) << plan.err;
  EXPECT_NE(plan.out.find("\"sh_order\": 5"), std::string::npos) << plan.out;
  EXPECT_NE(plan.out.find("\"environment\": \"builtin:sun\""), std::string::npos) << plan.out;
  // Messages name the option by its one spelling.
  const CliRun bad = run_cli("irradiance --sh 4 -o " + (dir / "d.json").string());
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
      std::string listed;  // "(alias: --cube-size, --cube)": every alias, spelled as an option
      for (std::string a : d.aliases) {
        std::replace(a.begin(), a.end(), '_', '-');
        listed += (listed.empty() ? "(alias: --" : ", --") + a;
      }
      if (!listed.empty()) {
        EXPECT_NE(help.find(listed + ")"), std::string::npos) << help;
      }
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
      {"bake", "--cube-sze 64", "--chain-size"},  // an alias meant: its option's canonical name
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
  EXPECT_NE(prefix.err.find("did you mean --chain-size or --cube-format?"), std::string::npos) << prefix.err;
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

// ---- One name per meaning (issue 34, "Names") -------------------------------------------------------
// A name means one thing on every command and in every front end, and one thing has one name
// (docs/SCENES.md, "One name per meaning"); the old names are aliases that every front end takes and
// that nothing the tool writes uses.

// A value for each bake option that has aliases: a new alias without a value here fails the tests.
const std::map<std::string, std::string>& aliased_bake_values() {
  static const std::map<std::string, std::string> v = {
      {"chain_size", "64"}, {"chain_max_error", "0.02"}, {"sh_order", "5"}, {"environment", "builtin:sun"}};
  return v;
}

// The same for the table kinds' parameters that have aliases (by kind, then parameter).
const std::map<std::string, std::map<std::string, std::string>>& aliased_table_values() {
  static const std::map<std::string, std::map<std::string, std::string>> v = {
      {"prefilter", {{"chain_size", "16"}, {"chain_max_error", "0.02"}}},
      {"irradiance", {{"irradiance_size", "4"}, {"sh_order", "5"}}},
      {"preview", {{"material", "FILE"}}},  // a material file the test writes
  };
  return v;
}

std::string dashed(std::string name) {
  std::replace(name.begin(), name.end(), '_', '-');
  return name;
}

// What parse_bake_options makes of `given` (name, text) pairs, as the plan's JSON.
std::string bake_plan_of(const std::vector<std::pair<std::string, std::string>>& given) {
  Params p;
  for (const auto& [name, text] : given) {
    const ParamDef* d = find_param_def_or_alias(bake_option_schema(), name);
    if (!d) throw Error("no bake option " + name);
    p.push_back({name, parse_param_text(*d, text, name)});
  }
  OptionNaming naming;
  naming.prefix = "bake";
  return plan_to_json(plan_bake(parse_bake_options(p, naming)));
}

// Every alias of a bake option gives the plan its canonical name gives, through the options' parser
// (the server's bodies and Python's bake_scene) and through `bake --dry-run --json`; the plan
// names only the canonical name; both together are refused with one line.
TEST(OneName, EveryBakeAliasGivesTheSamePlanAsItsName) {
  const std::string default_plan = bake_plan_of({});
  int checked = 0;
  for (const ParamDef& d : bake_option_schema())
    for (const std::string& alias : d.aliases) {
      SCOPED_TRACE(d.name + " / " + alias);
      ASSERT_TRUE(aliased_bake_values().count(d.name)) << "give the option a value in aliased_bake_values";
      const std::string value = aliased_bake_values().at(d.name);
      const std::string by_name = bake_plan_of({{d.name, value}});
      EXPECT_NE(by_name, default_plan) << "the value must change the plan, or the test proves nothing";
      EXPECT_EQ(bake_plan_of({{alias, value}}), by_name);
      EXPECT_EQ(by_name.find("\"" + alias + "\""), std::string::npos) << by_name;
      try {
        bake_plan_of({{d.name, value}, {alias, value}});
        ADD_FAILURE() << "both spellings taken";
      } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()),
                  "bake: " + d.name + ": given together with its alias " + alias + " (the same option): give one");
      }
      // The command line: the same plan, the same refusal, one line.
      const CliRun canonical = run_cli("bake --dry-run --json --" + dashed(d.name) + " " + value);
      const CliRun old = run_cli("bake --dry-run --json --" + dashed(alias) + " " + value);
      ASSERT_EQ(canonical.code, 0) << canonical.err;
      ASSERT_EQ(old.code, 0) << old.err;
      EXPECT_EQ(old.out, canonical.out);
      EXPECT_EQ(old.out.find("\"" + alias + "\""), std::string::npos) << old.out;
      const CliRun both =
          run_cli("bake --dry-run --" + dashed(d.name) + " " + value + " --" + dashed(alias) + " " + value);
      EXPECT_EQ(both.code, 2);
      EXPECT_EQ(test::count_lines(both.err), 1) << both.err;
      EXPECT_NE(both.err.find("--" + dashed(d.name) + ": given together with its alias --" + dashed(alias) +
                              " (the same option): give one"),
                std::string::npos)
          << both.err;
      ++checked;
    }
  EXPECT_GE(checked, 4);  // chain_size, chain_max_error, sh_order, environment at least
  // The old names of issue 34, by name.
  EXPECT_EQ(bake_plan_of({{"cube_size", "64"}}), bake_plan_of({{"chain_size", "64"}}));
  EXPECT_EQ(bake_plan_of({{"prefilter_max_error", "0.02"}}), bake_plan_of({{"chain_max_error", "0.02"}}));
  EXPECT_NE(bake_plan_of({{"chain_size", "64"}}).find("\"chain_size\": 64"), std::string::npos);
}

// Every alias of a table parameter: a job by either name is the same job, and writes only the
// canonical name; both together are refused with one line, in a job and on the command line.
TEST(OneName, EveryTableAliasGivesTheSameJobAsItsName) {
  const fs::path material = temp_dir("material") / "m.json";
  std::ofstream(material) << R"({"materials": [{"name": "a", "model": "gltf", "roughness": 0.5}]})";
  int checked = 0;
  for (TableKind k : table_kinds())
    for (const ParamDef& d : table_schema(k))
      for (const std::string& alias : d.aliases) {
        const std::string kind = table_kind_name(k);
        SCOPED_TRACE(kind + " " + d.name + " / " + alias);
        ASSERT_TRUE(aliased_table_values().count(kind) && aliased_table_values().at(kind).count(d.name))
            << "give the parameter a value in aliased_table_values";
        std::string value = aliased_table_values().at(kind).at(d.name), option_value = value;
        if (value == "FILE") {
          option_value = material.string();
          value = "\"" + option_value + "\"";
        }
        const auto job_of = [&](const std::string& fields) {
          Job job = parse_job(R"({"brdfbake_job": 1, "environment": "builtin:sun", "tables": [{"kind": ")" + kind +
                                  "\", " + fields + "}]}",
                              "job.json");
          validate_job(job);
          return job_to_json(job);
        };
        const std::string by_name = job_of("\"" + d.name + "\": " + value);
        EXPECT_EQ(job_of("\"" + alias + "\": " + value), by_name);
        EXPECT_NE(by_name.find("\"" + d.name + "\": " + value), std::string::npos) << by_name;
        EXPECT_EQ(by_name.find("\"" + alias + "\""), std::string::npos) << by_name;
        try {
          job_of("\"" + d.name + "\": " + value + ", \"" + alias + "\": " + value);
          ADD_FAILURE() << "both spellings taken";
        } catch (const Error& e) {
          EXPECT_EQ(std::string(e.what()), "job.json: tables[0]." + d.name + ": given together with its alias " +
                                               alias + " (the same option): give one");
        }
        const CliRun both =
            run_cli(table_kind_command(k) + " --env builtin:sun --" + dashed(d.name) + " " + option_value + " --" +
                    dashed(alias) + " " + option_value + " -o " + (temp_dir("both_" + d.name) / "x.ktx2").string());
        EXPECT_EQ(both.code, 2);
        EXPECT_EQ(test::count_lines(both.err), 1) << both.err;
        EXPECT_NE(both.err.find("--" + dashed(d.name) + ": given together with its alias --" + dashed(alias) +
                                " (the same option): give one"),
                  std::string::npos)
            << both.err;
        ++checked;
      }
  EXPECT_GE(checked, 6);  // prefilter size, max_error; irradiance cube_size, cube, sh; preview materials
  // Two aliases of one parameter together.
  const CliRun two = run_cli("irradiance --env builtin:sun --cube-size 4 --cube 4 -o " +
                             (temp_dir("two_aliases") / "x.ktx2").string());
  EXPECT_EQ(two.code, 2);
  EXPECT_NE(two.err.find("--irradiance-size: given as both --cube-size and --cube (the same option): give one"),
            std::string::npos)
      << two.err;
  // The command line by the old name writes the file the canonical name writes.
  const fs::path dir = temp_dir("prefilter_alias");
  const std::string common = " --env builtin:sun --min-size 4 --quiet -o ";
  const CliRun canonical = run_cli("prefilter --chain-size 8" + common + (dir / "a.ktx2").string());
  ASSERT_EQ(canonical.code, 0) << canonical.err;
  const CliRun old = run_cli("prefilter --size 8" + common + (dir / "b.ktx2").string());
  ASSERT_EQ(old.code, 0) << old.err;
  EXPECT_EQ(read_bytes(dir / "a.ktx2"), read_bytes(dir / "b.ktx2"));
}

// No canonical name has two meanings across the commands, and no meaning two canonical names:
// - the old names of issue 34 are canonical nowhere; no command's alias is one of its own names;
// - a name bake shares with a table command is that command's parameter (the same type, choices and
//   range), and setting it on bake sets that parameter of the planned table;
// - a name several table commands share is one of the generic names below, each with its meaning.
TEST(OneName, NoNameHasTwoMeaningsAcrossTheCommands) {
  std::map<std::string, std::vector<std::pair<std::string, const ParamDef*>>> uses;  // name -> (command, def)
  for (TableKind k : table_kinds())
    for (const ParamDef& d : table_schema(k)) uses[d.name].push_back({table_kind_command(k), &d});
  for (const ParamDef& d : bake_option_schema()) uses[d.name].push_back({"bake", &d});
  for (const char* old : {"cube_size", "prefilter_max_error"}) EXPECT_EQ(uses.count(old), 0u) << old;
  // a table's `materials` is its informative list of the materials that asked for it, no parameter
  EXPECT_EQ(uses.count("materials"), 0u);
  EXPECT_EQ(find_param_def(table_schema(TableKind::Prefilter), "size"), nullptr);
  EXPECT_EQ(find_param_def(table_schema(TableKind::Prefilter), "max_error"), nullptr);
  EXPECT_EQ(find_param_def(table_schema(TableKind::Irradiance), "cube_size"), nullptr);
  for (TableKind k : table_kinds())
    for (const ParamDef& d : table_schema(k))
      for (const std::string& a : d.aliases)
        EXPECT_EQ(find_param_def(table_schema(k), a), nullptr) << table_kind_name(k) << ": " << a;
  for (const ParamDef& d : bake_option_schema())
    for (const std::string& a : d.aliases) EXPECT_EQ(find_param_def(bake_option_schema(), a), nullptr) << a;

  // Shared with bake: the table's own parameter. chain_max_error on bake also takes 0 (no search,
  // the table's absent value), its only difference.
  for (const ParamDef& b : bake_option_schema())
    for (const auto& [command, t] : uses[b.name]) {
      if (command == "bake") continue;
      SCOPED_TRACE("bake and " + command + ": " + b.name);
      EXPECT_EQ(b.type, t->type);
      EXPECT_EQ(b.choices, t->choices);
      EXPECT_EQ(b.hi, t->hi);
      if (b.name != "chain_max_error") {
        EXPECT_EQ(b.lo, t->lo);
      }
    }
  const std::map<std::string, std::pair<std::string, std::string>> sets = {
      // bake option -> (table kind in the default plan, value)
      {"chain_size", {"prefilter", "32"}},   {"min_size", {"prefilter", "4"}},
      {"schedule", {"prefilter", "'sqrt'"}}, {"chain_max_error", {"prefilter", "0.02"}},
      {"sh_order", {"irradiance", "5"}},     {"sh_window", {"irradiance", "'lanczos'"}},
  };
  for (const auto& [name, kv] : sets) {
    SCOPED_TRACE(name);
    const ParamDef* b = find_param_def(bake_option_schema(), name);
    ASSERT_NE(b, nullptr);
    ASSERT_NE(find_param_def(table_schema(table_kind_from_name(kv.first)), name), nullptr)
        << "bake's option is not " << kv.first << "'s parameter of the same name";
    std::string text = kv.second;
    if (text.front() == '\'') text = text.substr(1, text.size() - 2);
    Params p = {{name, parse_param_text(*b, text, name)}};
    const Plan plan = plan_bake(parse_bake_options(p, OptionNaming{}));
    bool found = false;
    for (const TableRequest& t : plan.job.tables)
      if (table_kind_name(t.kind) == kv.first && t.find(name)) {
        EXPECT_EQ(param_value_text(*t.find(name)), kv.second);
        found = true;
      }
    EXPECT_TRUE(found) << "no " << kv.first << " table of the plan has " << name;
  }

  // Shared by table commands: the names of a command's own table or output, one meaning each.
  const std::map<std::string, std::string> generic = {
      {"size", "the command's one table: cells along its first axis (bake: lut_size, fresnel_size, ...)"},
      {"height", "the output's second axis: a table's cells, the preview image's pixels"},
      {"samples", "the estimator's samples per texel or cell"},
      {"estimator", "how the table's integral is estimated"},
      {"refinement", "the quadrature's refinement (prefilter's chain, preview's reference)"},
      {"target", "the engine target whose conventions the file follows"},
      {"model", "the analytic model of the command's table (the Fresnel model; the BRDF model)"},
      {"material",
       "the material the output is of (fresnel: a measured preset's name; eval, tabulate, preview: a file)"},
      {"name", "which material of the file"},
      {"layout", "how the output's values are arranged (a folder's images; tabulate's table)"},
      {"image_format", "a folder output's image format"},
      {"symbol", "a .h output's C symbol"},
      {"png_range", "a .png output's value range"},
      {"clamp_f16", "binary16 outputs: clamp beyond 65504 instead of refusing"},
      {"fast_math", "the evaluator's relaxed-math kernels"},
  };
  for (const auto& [name, list] : uses) {
    std::set<std::string> commands;
    for (const auto& [command, d] : list)
      if (command != "bake") commands.insert(command);
    if (commands.size() < 2) continue;
    std::string names;
    for (const auto& c : commands) names += " " + c;
    EXPECT_TRUE(generic.count(name)) << "'" << name << "' is a parameter of" << names
                                     << ": the same meaning? Add it to `generic` with its meaning, or rename it";
  }
  // bake's several tables: each size names its table.
  for (const char* name : {"size", "max_error"}) EXPECT_EQ(find_param_def(bake_option_schema(), name), nullptr);
}

}  // namespace
}  // namespace brdfbake
