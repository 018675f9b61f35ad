// The family registry: every parameter has one definition that the job parser, the command line and
// the spec structs agree on, and a table baked by its command and by the equivalent job is the same.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "brdfbake/dfg_lut.hpp"
#include "brdfbake/fresnel.hpp"
#include "brdfbake/job.hpp"
#include "brdfbake/tables.hpp"
#include "brdfbake/thin_film.hpp"
#include "enum_names.hpp"
#include "families/brdf_eval/model.hpp"
#include "families/dfg_lut/model.hpp"
#include "families/family.hpp"
#include "families/fresnel/model.hpp"
#include "families/irradiance/model.hpp"
#include "families/prefilter/model.hpp"
#include "families/preview/model.hpp"
#include "support/cli_runner.hpp"
#include "support/field_count.hpp"
#include "support/temp_dir.hpp"
#include "support/tolerances.hpp"

namespace {

namespace fs = std::filesystem;
using namespace brdfbake;
using brdfbake::test::CliRun;
using brdfbake::test::field_count;

// A fresh, empty folder `name` in the test's temporary folder (removed when the test ends).
fs::path temp_dir(const std::string& name) { return brdfbake::test::test_temp_dir(name); }

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// ---- Every spec field has a schema entry -----------------------------------------------------------

// For each spec struct: its fields, each with the parameter that sets it, or the reason none does, as
// the family's schema binds them (families/spec_schema.hpp). When a field is added to a spec,
// field_count changes and this test fails until the field is bound (or listed as internal).
void expect_bound(TableKind kind, size_t fields, const char* spec) {
  const std::vector<detail::SpecField> bound = detail::family_of(kind).spec_fields(kind);
  EXPECT_EQ(fields, bound.size()) << spec << " has " << fields << " fields but " << table_kind_name(kind)
                                  << "'s schema binds " << bound.size()
                                  << ": bind the new field to a parameter in its family's schema";
  const auto& schema = table_schema(kind);
  const std::set<std::string> common = {"precision", "kind"};
  std::set<std::string> seen;
  for (const auto& f : bound) {
    EXPECT_TRUE(seen.insert(f.field).second) << spec << "." << f.field << " is bound twice";
    if (f.parameter.empty()) {
      EXPECT_FALSE(f.reason.empty()) << spec << "." << f.field << " has no parameter and no reason";
      continue;
    }
    if (common.count(f.parameter)) continue;
    EXPECT_NE(find_param_def(schema, f.parameter), nullptr)
        << spec << "." << f.field << " maps to '" << f.parameter << "', which " << table_kind_name(kind) << " lacks";
  }
}

// Each enum's one table of names: every value has one name that reads back as the value, the names
// are distinct, an unknown name is refused naming every alternative, and the public *_name /
// *_from_name functions are the table's.
template <class E, size_t N>
void expect_names_round_trip(const detail::EnumName<E> (&table)[N], const char* (*name_of)(E),
                             E (*from_name)(const std::string&)) {
  std::set<std::string> seen;
  for (const auto& entry : table) {
    EXPECT_TRUE(seen.insert(entry.name).second) << entry.name << " twice";
    EXPECT_EQ(detail::enum_from_name(table, entry.name, "x"), entry.value) << entry.name;
    EXPECT_STREQ(name_of(entry.value), entry.name);
    EXPECT_EQ(from_name(entry.name), entry.value) << entry.name;
  }
  try {
    from_name("no-such-name");
    ADD_FAILURE() << "an unknown name was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(detail::enum_alternatives(table)), std::string::npos) << e.what();
  }
}

TEST(Registry, EveryEnumNameRoundTrips) {
  expect_names_round_trip(detail::kLutKindNames, lut_kind_name, lut_kind_from_name);
  expect_names_round_trip(detail::kEstimatorNames, estimator_name, estimator_from_name);
  expect_names_round_trip(detail::kSheenVisibilityNames, sheen_visibility_name, sheen_visibility_from_name);
  expect_names_round_trip(detail::kLutAxisNames, lut_axis_name, lut_axis_from_name);
  expect_names_round_trip(detail::kEnvDistributionNames, env_distribution_name, env_distribution_from_name);
  expect_names_round_trip(detail::kRoughnessScheduleNames, roughness_schedule_name, roughness_schedule_from_name);
  expect_names_round_trip(detail::kEnvEstimatorNames, env_estimator_name, env_estimator_from_name);
  expect_names_round_trip(detail::kShWindowNames, sh_window_name, sh_window_from_name);
  expect_names_round_trip(detail::kTableLayoutNames, table_layout_name, table_layout_from_name);
  expect_names_round_trip(detail::kFresnelTableKindNames, fresnel_table_kind_name, fresnel_table_kind_from_name);
  expect_names_round_trip(detail::preview::kBackgroundNames, preview_background_name, preview_background_from_name);
  EXPECT_EQ(detail::enum_alternatives(detail::kRoughnessScheduleNames), "linear, filament, sqrt or babylon");
}

// The schemas offer exactly the names their tables hold (one_of generated from the tables).
TEST(Registry, SchemaChoicesAreTheEnumTables) {
  auto choices = [](TableKind kind, const std::string& param) {
    for (const ParamDef& d : table_schema(kind))
      if (d.name == param) return d.choices;
    ADD_FAILURE() << table_kind_name(kind) << " has no parameter " << param;
    return std::vector<std::string>{};
  };
  EXPECT_EQ(choices(TableKind::Prefilter, "schedule"), detail::enum_names(detail::kRoughnessScheduleNames));
  EXPECT_EQ(choices(TableKind::Prefilter, "distribution"), detail::enum_names(detail::kEnvDistributionNames));
  EXPECT_EQ(choices(TableKind::Ggx, "estimator"), detail::enum_names(detail::kEstimatorNames));
  EXPECT_EQ(choices(TableKind::Irradiance, "sh_window"), detail::enum_names(detail::kShWindowNames));
  EXPECT_EQ(choices(TableKind::Tabulate, "layout"), detail::enum_names(detail::kTableLayoutNames));
  EXPECT_EQ(choices(TableKind::Preview, "background"), detail::enum_names(detail::preview::kBackgroundNames));
}

TEST(Registry, EverySpecFieldHasASchemaEntry) {
  for (TableKind kind : {TableKind::Ggx, TableKind::GgxMultiscatter, TableKind::Charlie})
    expect_bound(kind, field_count<LutSpec>(), "LutSpec");
  EXPECT_NE(find_param_def(table_schema(TableKind::Charlie), "sheen_visibility"), nullptr);
  expect_bound(TableKind::Fresnel, field_count<FresnelSpec>(), "FresnelSpec");
  expect_bound(TableKind::Preview, field_count<PreviewSpec>(), "PreviewSpec");
  expect_bound(TableKind::ThinFilm, field_count<ThinFilmSpec>(), "ThinFilmSpec");
  expect_bound(TableKind::Prefilter, field_count<PrefilterSpec>(), "PrefilterSpec");
  expect_bound(TableKind::Irradiance, field_count<IrradianceSpec>(), "IrradianceSpec");
  expect_bound(TableKind::Tabulate, field_count<TabulateSpec>(), "TabulateSpec");
  expect_bound(TableKind::Eval, field_count<EvalOptions>(), "EvalOptions");
}

// ---- Every parameter is a job field and a command-line option -------------------------------------

// A value the definition accepts (its default, or a point of its range).
ParamValue sample_value(const ParamDef& d) {
  if (d.fallback) return *d.fallback;
  switch (d.type) {
    case ParamType::Int:
      return std::isfinite(d.lo) ? d.lo : 1.0;
    case ParamType::Number:
      return std::isfinite(d.hi) ? d.hi : 1.0;
    case ParamType::Name:
      return d.choices.empty() ? std::string("x") : d.choices.front();
    case ParamType::Path:
      return std::string("x.json");
    case ParamType::Flag:
      return true;
    case ParamType::Color:
      return std::isfinite(d.hi) ? d.hi : 1.0;
    case ParamType::Range:
      return std::vector<double>{0.0, 1.0};
    case ParamType::IntList:
      return std::vector<double>{8.0};
  }
  return 1.0;
}

TEST(Registry, EveryParameterIsAJobFieldAndAnOption) {
  std::map<std::string, std::string> help;  // command -> its --help
  for (TableKind kind : table_kinds()) {
    const std::string command = table_kind_command(kind);
    if (!help.count(command)) {
      const CliRun r = brdfbake::test::run_cli(command + " --help");
      ASSERT_EQ(r.code, 0) << command << ": " << r.err;
      help[command] = r.out;
    }
    for (const ParamDef& d : table_schema(kind)) {
      // the job parser knows the field: whatever else it says, it is not "unknown field"
      std::string text =
          "{\"tables\": [{\"kind\": \"" + std::string(table_kind_name(kind)) + "\", \"" + d.name + "\": ";
      const ParamValue v = sample_value(d);
      if (auto b = std::get_if<bool>(&v))
        text += *b ? "true" : "false";
      else if (auto x = std::get_if<double>(&v))
        text += std::to_string(*x);
      else if (auto s = std::get_if<std::string>(&v))
        text += "\"" + *s + "\"";
      else {
        text += "[";
        const auto& a = std::get<std::vector<double>>(v);
        for (size_t i = 0; i < a.size(); ++i) text += (i ? ", " : "") + std::to_string(a[i]);
        text += "]";
      }
      text += "}]}";
      try {
        parse_job(text, "job.json");
      } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()).find("unknown field"), std::string::npos) << text << " -> " << e.what();
      }
      // the command has the option, spelled as the schema says
      const bool negated = d.type == ParamType::Flag && d.fallback && std::get<bool>(*d.fallback);
      const std::string option = d.cli_name().size() == 1 ? "-" + d.cli_name() + " arg"
                                                          : "--" + std::string(negated ? "no-" : "") + d.cli_name();
      EXPECT_NE(help[command].find(option), std::string::npos) << command << " lacks " << option << " for " << d.name;
      EXPECT_FALSE(d.help.empty()) << table_kind_name(kind) << "." << d.name << " has no help";
    }
  }
}

// ---- A command and the equivalent job write the same file ----------------------------------------

// The file's bytes with the time of writing blanked out (an EXR's capDate attribute, which the image
// library stamps): the only thing a command and a job may write differently.
std::string without_dates(std::string bytes) {
  const std::string key = std::string("capDate") + '\0' + "string" + '\0';
  for (size_t at = bytes.find(key); at != std::string::npos; at = bytes.find(key, at + 1)) {
    const size_t value = at + key.size() + 4;  // after the int32 size
    for (size_t k = value; k < value + 19 && k < bytes.size(); ++k) bytes[k] = '#';
  }
  return bytes;
}

struct Parity {
  std::string command;  // options after the command, without -o
  std::string table;    // the job's table, without output
  std::string file;     // the output's file name
};

TEST(Registry, CommandAndJobWriteTheSameFile) {
  const fs::path dir = temp_dir("parity");
  const fs::path cli = dir / "cli", job_dir = dir / "job";
  fs::create_directories(cli);
  {
    std::ofstream(dir / "materials.json")
        << R"({"materials": [{"name": "red", "model": "disney", "baseColor": [0.8, 0.1, 0.1], "roughness": 0.4}]})";
    std::ofstream(dir / "pairs.csv") << "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n0,0,1,0,0,1\n0.3,0.1,0.9,-0.2,0.4,0.8\n";
  }
  const std::string mats = (dir / "materials.json").string(), pairs = (dir / "pairs.csv").string();
  const std::vector<Parity> cases = {
      {"lut --kind ggx-multiscatter --size 16", R"("kind": "ggx-multiscatter", "size": 16)", "dfg.exr"},
      {"lut --kind charlie --size 8 --sheen-visibility neubelt",
       R"("kind": "charlie", "size": 8, "sheen_visibility": "neubelt")", "charlie.csv"},
      {"fresnel --model f82-tint --f0 0.9,0.6,0.2 --f82 0.8,0.7,0.6 --size 16",
       R"("kind": "fresnel", "model": "f82-tint", "f0": [0.9, 0.6, 0.2], "f82": [0.8, 0.7, 0.6], "size": 16)",
       "f82.csv"},
      {"fresnel --model schlick --table 2d --size 8 --height 4",
       R"("kind": "fresnel", "model": "schlick", "table": "2d", "size": 8, "height": 4)", "schlick2d.exr"},
      {"thin-film --base-ior 1.5 --size 8 --height 4",
       R"("kind": "thin-film", "base_ior": 1.5, "size": 8, "height": 4)", "film.exr"},
      {"prefilter --env builtin:sun --size 8 --min-size 4", R"("kind": "prefilter", "size": 8, "min_size": 4)",
       "chain.ktx2"},
      {"irradiance --env builtin:sun --sh 5", R"("kind": "irradiance", "sh_order": 5)", "sh.json"},
      {"eval --material " + mats + " -i " + pairs,
       R"("kind": "eval", "material": ")" + mats + R"(", "input": ")" + pairs + "\"", "f.csv"},
      {"tabulate --material " + mats + " --layout albedo --res 8",
       R"("kind": "tabulate", "material": ")" + mats + R"(", "layout": "albedo", "res": 8)", "albedo.csv"},
  };
  std::string tables;
  for (const auto& c : cases)
    tables += std::string(tables.empty() ? "" : ",\n") + "{" + c.table + ", \"output\": \"" + c.file + "\"}";
  std::ofstream(dir / "job.json") << "{\"environment\": \"builtin:sun\", \"tables\": [" << tables << "]}";
  const CliRun j = brdfbake::test::run_cli("run " + (dir / "job.json").string() + " --quiet -o " + job_dir.string());
  ASSERT_EQ(j.code, 0) << j.err;
  for (const auto& c : cases) {
    const CliRun r = brdfbake::test::run_cli(c.command + " --quiet -o " + (cli / c.file).string());
    ASSERT_EQ(r.code, 0) << c.command << ": " << r.err;
    const std::string a = without_dates(read_file(cli / c.file)), b = without_dates(read_file(job_dir / c.file));
    ASSERT_FALSE(a.empty()) << c.file;
    EXPECT_TRUE(a == b) << c.command << ": the command's " << c.file << " (" << a.size()
                        << " bytes) differs from the job's (" << b.size() << " bytes)";
  }
  fs::remove_all(dir.parent_path());
}

// ---- Kinds that only the command line reached before -----------------------------------------------

TEST(Registry, EveryFresnelModelAndTheTwoDimensionalTablesRunAsJobs) {
  const fs::path dir = temp_dir("fresnel-jobs");
  std::ofstream(dir / "job.json") << R"({"tables": [
    {"kind": "fresnel", "model": "f82-tint", "f0": [0.9, 0.6, 0.2], "f82": 0.7, "size": 16, "output": "f82.csv"},
    {"kind": "fresnel", "model": "empirical", "bias": 0.1, "scale": 0.9, "power": 5, "size": 16, "output": "emp.csv"},
    {"kind": "fresnel", "model": "schlick-metallic", "base_color": [0.9, 0.6, 0.3], "metallic": 0.5, "size": 16, "output": "sm.csv"},
    {"kind": "fresnel", "model": "dielectric", "table": "2d", "size": 16, "height": 8, "range": [1.2, 2.0], "output": "d2.csv"}]})";
  const CliRun r =
      brdfbake::test::run_cli("run " + (dir / "job.json").string() + " --quiet -o " + (dir / "out").string());
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* f : {"f82.csv", "emp.csv", "sm.csv", "d2.csv"}) {
    const std::string text = read_file(dir / "out" / f);
    // the file records the bound measured against the double reference
    const auto at = text.find("# error_bound_mixed: ");
    ASSERT_NE(at, std::string::npos) << f;
    const double bound = std::stod(text.substr(at + 21));
    EXPECT_LT(bound, test::kFresnelFp32) << f << ": fp32 Fresnel against the reference";
  }
  // empirical at normal incidence: clamp(bias + scale * 0^power) = bias; the first cell is cos = 1/32
  const std::string emp = read_file(dir / "out" / "emp.csv");
  EXPECT_NE(emp.find("cos_theta,r,g,b"), std::string::npos);
  // schlick-metallic with metallic 0.5: F0 = mix(0.04, base, 0.5); at cos = 1 - 1/32 the red channel
  // is F0 + (1 - F0)(1/32)^5, within fp32 of F0 = 0.47
  const std::string sm = read_file(dir / "out" / "sm.csv");
  const auto last = sm.rfind('\n', sm.size() - 2);
  const std::string row = sm.substr(last + 1);
  EXPECT_NEAR(std::stod(row.substr(row.find(',') + 1)), 0.47 + 0.53 * std::pow(1.0 / 32, 5), test::kFresnelFp32) << row;
  fs::remove_all(dir.parent_path());
}

TEST(Registry, FresnelFilesCarryTheirErrorBound) {
  const fs::path dir = temp_dir("fresnel-bound");
  const CliRun r = brdfbake::test::run_cli("fresnel --model conductor --material gold --size 32 --quiet -o " +
                                           (dir / "gold.csv").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string text = read_file(dir / "gold.csv");
  EXPECT_NE(text.find("# error_bound_mixed: "), std::string::npos) << text.substr(0, 400);
  EXPECT_NE(text.find("# integration_error_bound_definition: max |table - scalar double reference|"),
            std::string::npos);
  EXPECT_NE(text.find("# error_definition: bound on |stored - converged| / max(1, |converged|)"), std::string::npos);
  fs::remove_all(dir.parent_path());
}

TEST(Registry, TheJobReferenceInTheDocsIsTheSchemas) {
  const std::string doc = read_file(fs::path(BRDFBAKE_SOURCE_DIR) / "docs" / "SCENES.md");
  const auto a = doc.find("<!-- kinds:begin -->\n"), b = doc.find("<!-- kinds:end -->");
  ASSERT_NE(a, std::string::npos);
  ASSERT_NE(b, std::string::npos);
  const CliRun r = brdfbake::test::run_cli("kinds --markdown");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(doc.substr(a + 21, b - a - 21) == r.out)
      << "docs/SCENES.md's parameter table is out of date: run scripts/update_docs.sh";
}

TEST(Registry, ValidationNamesTheFieldAsEachFrontEndSpellsIt) {
  TableRequest t;
  t.kind = TableKind::Irradiance;
  t.params = {{"sh_order", 4.0}};
  FieldNaming job;
  job.prefix = "job.json: tables[2]";
  try {
    validate_table(t, job);
    ADD_FAILURE() << "sh_order 4 accepted";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "job.json: tables[2].sh_order: must be 3 or 5 (got 4)");
  }
  FieldNaming cli;
  cli.cli = true;
  t.params = {{"sh_order", 4.0}};
  try {
    validate_table(t, cli);
    ADD_FAILURE() << "sh_order 4 accepted";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "--sh-order: must be 3 or 5 (got 4)");  // the option by its one spelling (issue 24)
  }
}

}  // namespace
