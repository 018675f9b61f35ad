// What a new user stumbled on (issue 24, "A new user's stumbles"), each as a class:
// - option names: every parameter is the option --NAME of its job field (with - for _) on every
//   command, shorter spellings are aliases listed in --help, and an unknown option on any command
//   says which known one is closest.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "brdfbake/params.hpp"
#include "brdfbake/plan.hpp"
#include "brdfbake/tables.hpp"
#include "support/cli_runner.hpp"

namespace brdfbake {
namespace {

namespace fs = std::filesystem;
using test::CliRun;
using test::run_cli;

fs::path temp_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("brdfbake-new-user-" + std::to_string(::getpid())) / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// Help text with its line wrapping undone: runs of white space as one space.
std::string unwrapped(const std::string& text) {
  std::string s;
  for (char c : text)
    if (!std::isspace(static_cast<unsigned char>(c))) s += c;
    else if (!s.empty() && s.back() != ' ') s += ' ';
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
  const CliRun job_names = run_cli("irradiance --environment builtin:sun --sh-order 5 --cube-size 4" + common +
                                   (dir / "a.ktx2").string());
  ASSERT_EQ(job_names.code, 0) << job_names.err;
  const CliRun aliases =
      run_cli("irradiance --env builtin:sun --sh 5 --cube 4" + common + (dir / "b.ktx2").string());
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
      {"bake", "--cube-sze 64", "--cube-size"},      {"run", "--dry-rn x.json", "--dry-run"},
      {"serve", "--max-queu 3", "--max-queue"},      {"devices", "--jsn", "--json"},
      {"kinds", "--markdwn", "--markdown"},          {"lut", "--sise 8", "--size"},
      {"fresnel", "--materal gold", "--material"},   {"thin-film", "--film-iorr 1.3", "--film-ior"},
      {"prefilter", "--distribtion ggx", "--distribution"}, {"irradiance", "--sh_order 5", "--sh-order"},
      {"eval", "--materal m.json", "--material"},    {"tabulate", "--layot merl", "--layout"},
      {"view", "--exposur 2 x.ktx2 -o s.png", "--exposure"}, {"report", "--kindss ggx", "--kinds"},
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

}  // namespace
}  // namespace brdfbake
