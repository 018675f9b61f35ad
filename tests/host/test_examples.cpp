// examples/README.md: every command of its `sh` blocks runs, in order, in a temporary folder holding
// a copy of examples/, and what each writes exists and is valid (read back by `brdfbake view`, the
// PNG reader or the JSON parser).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "io/png_image.hpp"
#include "support/cli_runner.hpp"
#include "support/temp_dir.hpp"

namespace brdfbake {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The lines of the ```sh blocks.
std::vector<std::string> readme_commands(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  std::string line;
  bool in_block = false;
  while (std::getline(in, line)) {
    if (line.rfind("```", 0) == 0) {
      in_block = !in_block && line == "```sh";
      continue;
    }
    if (in_block && !line.empty() && line[0] != '#') out.push_back(line);
  }
  return out;
}

// The value after `-o` in a command, or "".
std::string output_of(const std::string& command) {
  std::istringstream in(command);
  std::string word, prev;
  while (in >> word) {
    if (prev == "-o") return word;
    prev = word;
  }
  return "";
}

TEST(Examples, EveryCommandOfTheReadmeRuns) {
  const fs::path src = fs::path(BRDFBAKE_SOURCE_DIR) / "examples";
  const std::vector<std::string> commands = readme_commands(read(src / "README.md"));
  ASSERT_GE(commands.size(), 8u) << "the README's sh blocks";
  const fs::path dir = brdfbake::test::test_temp_dir("examples");
  fs::copy(src, dir / "examples", fs::copy_options::recursive);
  std::vector<std::string> outputs;
  for (const std::string& c : commands) {
    SCOPED_TRACE(c);
    ASSERT_EQ(c.rfind("brdfbake ", 0), 0u) << "a command of the README runs brdfbake";
    // The runner puts the tool's path first: the folder change goes in front of it.
    const test::CliRun r = test::run_cli(c.substr(9), {}, "cd '" + dir.string() + "' &&");
    ASSERT_EQ(r.code, 0) << r.err;
    std::string out = output_of(c);
    if (c.rfind("brdfbake run ", 0) == 0) {
      const json job = json::parse(read(dir / c.substr(13)));
      out = job["output_dir"].get<std::string>();
      const json manifest = json::parse(read(dir / out / "manifest.json"));
      EXPECT_EQ(manifest["files"].size(), job["tables"].size());
      for (const json& f : manifest["files"])
        EXPECT_TRUE(fs::exists(dir / out / f["path"].get<std::string>())) << f["path"];
    }
    ASSERT_FALSE(out.empty()) << "every command names its output";
    EXPECT_TRUE(fs::exists(dir / out)) << out;
    outputs.push_back(out);
  }
  // Valid: pictures decode, reports parse, every other output reads back through view.
  std::string tables;
  for (const std::string& o : outputs) {
    const fs::path p = dir / o;
    if (p.extension() == ".png") {
      const io::PngImage im = io::read_png(p.string());
      EXPECT_GT(im.width, 100) << o;
      EXPECT_GT(im.height, 100) << o;
    } else if (p.extension() == ".html") {
      fs::path j = p;
      j.replace_extension(".json");
      const json report = json::parse(read(j));
      EXPECT_FALSE(report["dfg"].empty());
      EXPECT_FALSE(report["fresnel"].empty());
      EXPECT_NE(read(p).find("<svg"), std::string::npos);
    } else {
      tables += " '" + p.string() + "'";
    }
    if (fs::is_directory(p) && fs::exists(p / "contact_sheet.png")) io::read_png((p / "contact_sheet.png").string());
  }
  const test::CliRun v = test::run_cli("view" + tables + " -o '" + (dir / "check.png").string() + "'");
  EXPECT_EQ(v.code, 0) << v.err;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace brdfbake
