// The cases that bake a small table of every kernel family (issue 17): hand-written ones (estimators
// and layouts) and every kind's example request (table_kind_example), so that a new family is
// covered without a new case. Shared by the tests that bake each family on two devices
// (test_second_device.cpp) and in two kernel shapes (test_kernel_shape.cpp).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "brdfbake/environment.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/job.hpp"
#include "brdfbake/tables.hpp"
#include "support/tolerances.hpp"

namespace brdfbake::test {

struct FamilyCase {
  std::string name;
  std::string table;     // the job's table, JSON; empty: the example request of `kind`
  double tolerance = 0;  // when the result records no bound
  TableKind kind = TableKind::Ggx;
};

// The fp32 tolerance of a kind's device tests (tests/support/tolerances.hpp), for results that
// record no bound of their own; 0 for the kinds that record one.
inline double example_tolerance(TableKind kind) {
  switch (kind) {
    case TableKind::Ggx:
    case TableKind::GgxMultiscatter:
    case TableKind::Charlie:
      return 0;  // the calibrated bound the result records
    case TableKind::Fresnel:
    case TableKind::ThinFilm:
      return test::kFresnelFp32;
    case TableKind::Prefilter:
    case TableKind::Irradiance:
      return test::kEnvFp32VsFp64;
    case TableKind::Eval:
      return test::kBrdfFp32;
    case TableKind::Tabulate:
      return test::kBrdfTableFp32;
    case TableKind::Preview:
      return 0;  // not among the examples here (see cases())
  }
  return 0;
}

inline std::string source_path(const char* relative) { return std::string(BRDFBAKE_SOURCE_DIR) + "/" + relative; }

inline std::vector<FamilyCase> family_cases() {
  const std::string mats = source_path("examples/materials.json"), pairs = source_path("examples/pairs.csv");
  std::vector<FamilyCase> list = {
      {"lut_ggx_quadrature", R"({"kind": "ggx", "size": 4, "samples": 256})", 0},
      {"lut_ggx_vndf", R"({"kind": "ggx", "size": 4, "estimator": "vndf", "samples": 256})", 0},
      {"lut_ggx_ndf_fp64", R"({"kind": "ggx", "size": 4, "estimator": "ndf", "samples": 128, "precision": "fp64"})", 0},
      {"lut_multiscatter", R"({"kind": "ggx-multiscatter", "size": 4, "samples": 256})", 0},
      {"lut_charlie_uniform", R"({"kind": "charlie", "size": 4, "estimator": "uniform", "samples": 256})", 0},
      {"fresnel_conductor",
       R"({"kind": "fresnel", "model": "conductor", "n": [0.2, 0.9, 1.1], "k": [3.9, 2.4, 2.2], "size": 16})",
       kFresnelFp32},
      {"fresnel_dielectric_2d", R"({"kind": "fresnel", "model": "dielectric", "table": "2d", "size": 8})",
       kFresnelFp32},
      {"thin_film", R"({"kind": "thin-film", "base_ior": 1.5, "size": 4})", kFresnelFp32},
      {"prefilter_quadrature", R"({"kind": "prefilter", "environment": "builtin:sun", "size": 8, "min_size": 4})",
       kEnvFp32VsFp64},
      {"prefilter_sampling", R"({"kind": "prefilter", "environment": "builtin:sun", "size": 8, "min_size": 4,
                                 "estimator": "sampling", "samples": 64})",
       kEnvFp32VsFp64},
      {"prefilter_charlie", R"({"kind": "prefilter", "environment": "builtin:studio", "distribution": "charlie",
                                "size": 4, "min_size": 4})",
       kEnvFp32VsFp64},
      {"irradiance_cube", R"({"kind": "irradiance", "environment": "builtin:sun", "cube_size": 4, "source_size": 8})",
       kEnvFp32VsFp64},
      {"eval", R"({"kind": "eval", "material": ")" + mats + R"(", "name": "velvet", "input": ")" + pairs + "\"}",
       kBrdfFp32},
      {"tabulate_grid", R"({"kind": "tabulate", "material": ")" + mats + R"(", "name": "red-plastic", "layout": "grid",
                            "res": [4, 4, 4]})",
       kBrdfTableFp32},
      {"tabulate_slice", R"({"kind": "tabulate", "material": ")" + mats + R"(", "name": "gold", "layout": "slice",
                             "res": [8, 8]})",
       kBrdfTableFp32},
      {"tabulate_albedo", R"({"kind": "tabulate", "material": ")" + mats + R"(", "name": "velvet", "layout": "albedo",
                              "res": [4]})",
       kBrdfTableFp32},
  };
  for (TableKind kind : table_kinds()) {
    // The preview's reference render interpreted by Oclgrind takes minutes even at its example's
    // 96x48; tests/device/test_preview.cpp holds its kernels to the scalar reference.
    if (kind == TableKind::Preview) continue;
    std::string name = std::string("example_") + table_kind_name(kind);
    std::replace(name.begin(), name.end(), '-', '_');
    list.push_back({name, "", example_tolerance(kind), kind});
  }
  return list;
}

// A case's request with its inputs (the environment read, the example's pairs): held in place,
// since `inputs` points into it.
struct PreparedCase {
  TableExample example;
  EnvImage env;
  BakeInputs inputs;
  const TableRequest& request() const { return example.request; }
};

inline std::unique_ptr<PreparedCase> prepare_case(const FamilyCase& c) {
  auto p = std::make_unique<PreparedCase>();
  if (c.table.empty()) {
    p->example = table_kind_example(c.kind);
  } else {
    const Job job = parse_job(R"({"brdfbake_job": 1, "output_dir": "unused", "tables": [)" + c.table + "]}", c.name);
    if (job.tables.size() != 1)
      throw Error(c.name + ": the case holds " + std::to_string(job.tables.size()) + " tables");
    p->example.request = job.tables[0];
    if (p->example.request.environment.empty()) p->example.request.environment = job.environment;
  }
  const TableRequest& t = p->example.request;
  if (table_kind_uses_environment(t.kind)) {
    p->env = load_environment(t.environment);
    p->inputs.environment = &p->env;
  }
  if (!p->example.pairs.empty()) {
    p->inputs.pairs = p->example.pairs.data();
    p->inputs.pair_count = p->example.pairs.size() / 6;
  }
  return p;
}

inline std::string case_test_name(const ::testing::TestParamInfo<FamilyCase>& i) { return i.param.name; }

}  // namespace brdfbake::test
