// `brdfbake report --kinds kernels` (issue 36): the counted-op arithmetic with known counts and
// injected times, the count table's consistency, the page and JSON of an injected report, and the
// device's peak and bandwidth kernels giving positive figures (no timed assertion).
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "brdfbake/report.hpp"
#include "support/device_fixture.hpp"

namespace brdfbake {
namespace {

KernelRow counted_row(double units, double seconds, double flops_per_unit, double bytes_per_unit) {
  KernelRow r;
  r.id = "test fp32";
  r.kernel = "test_kernel";
  r.unit = "texel";
  r.precision = "fp32";
  r.units = units;
  r.device_seconds = seconds;
  r.counted = true;
  r.flops_per_unit = flops_per_unit;
  r.bytes_per_unit = bytes_per_unit;
  return r;
}

TEST(KernelRoofline, ComputeBoundRowFromKnownCountsAndTimes) {
  // 1e6 texels in 10 ms, 2000 flops and 40 bytes a texel, against 400 GFLOP/s and 20 GB/s (ridge 20):
  // 1e8 texels/s, 200 GFLOP/s, 4 GB/s, 50 flops a byte, compute-bound at half the peak.
  KernelRow r = counted_row(1e6, 0.01, 2000, 40);
  place_kernel_row(r, 400.0, 20.0, 2);
  EXPECT_DOUBLE_EQ(r.units_per_second, 1e8);
  EXPECT_DOUBLE_EQ(r.gflops, 200.0);
  EXPECT_DOUBLE_EQ(r.gbytes_per_second, 4.0);
  EXPECT_DOUBLE_EQ(r.intensity, 50.0);
  EXPECT_EQ(r.bound, "compute");
  EXPECT_DOUBLE_EQ(r.fraction, 0.5);
  EXPECT_DOUBLE_EQ(r.flops_fraction, 0.5);
  EXPECT_TRUE(r.limit.empty()) << r.limit;  // above 25 %: no cause named
}

TEST(KernelRoofline, MemoryBoundRowIsAFractionOfTheBandwidth) {
  // 2 flops and 16 bytes a cell (0.125 flops a byte, below the ridge of 20): 1e9 cells/s move 16 GB/s,
  // 80 % of the triad's 20 GB/s, whatever its 2 GFLOP/s are against the compute peak.
  KernelRow r = counted_row(1e7, 0.01, 2, 16);
  place_kernel_row(r, 400.0, 20.0, 2);
  EXPECT_EQ(r.bound, "memory");
  EXPECT_DOUBLE_EQ(r.gflops, 2.0);
  EXPECT_DOUBLE_EQ(r.gbytes_per_second, 16.0);
  EXPECT_DOUBLE_EQ(r.fraction, 0.8);
  EXPECT_DOUBLE_EQ(r.flops_fraction, 0.005);
  EXPECT_TRUE(r.limit.empty());
}

TEST(KernelRoofline, AboveTheTriadSaysTheCachesServeIt) {
  // 1 flop and 8 bytes a texel at 5e9 texels/s: 40 GB/s against the triad's 20, 5 GFLOP/s of 400.
  KernelRow r = counted_row(5e7, 0.01, 1, 8);
  r.walk = true;
  place_kernel_row(r, 400.0, 20.0, 2);
  EXPECT_EQ(r.bound, "memory");
  EXPECT_DOUBLE_EQ(r.fraction, 2.0);
  EXPECT_DOUBLE_EQ(r.flops_fraction, 0.0125);
  EXPECT_NE(r.limit.find("the caches serve them"), std::string::npos) << r.limit;
  EXPECT_NE(r.limit.find("1.2% of the flops peak"), std::string::npos) << r.limit;
  EXPECT_NE(r.limit.find("walk"), std::string::npos) << r.limit;
}

TEST(KernelRoofline, MemorySideBelowAQuarterSaysBandwidthDoesNotBoundIt) {
  // 2 flops and 16 bytes a cell at 1e8 cells/s: 1.6 GB/s, 8 % of the triad's 20; 6 % special functions.
  KernelRow r = counted_row(1e6, 0.01, 2, 16);
  r.special_share = 0.06;
  place_kernel_row(r, 400.0, 20.0, 2);
  EXPECT_EQ(r.bound, "memory");
  EXPECT_DOUBLE_EQ(r.fraction, 0.08);
  EXPECT_NE(r.limit.find("bandwidth does not bound it"), std::string::npos) << r.limit;
  EXPECT_NE(r.limit.find("transcendentals: 6.0%"), std::string::npos) << r.limit;
  // and with nothing else to name, it says so
  KernelRow bare = counted_row(1e6, 0.01, 2, 16);
  place_kernel_row(bare, 400.0, 20.0, 2);
  EXPECT_NE(bare.limit.find("none of the causes checked here"), std::string::npos) << bare.limit;
  // 4 % special functions is not named
  KernelRow few = counted_row(1e6, 0.01, 2, 16);
  few.special_share = 0.04;
  place_kernel_row(few, 400.0, 20.0, 2);
  EXPECT_EQ(few.limit.find("transcendentals"), std::string::npos) << few.limit;
}

TEST(KernelRoofline, BelowAQuarterOfThePeakSaysWhatBoundsIt) {
  // 10 GFLOP/s of 400 (2.5 %), with 40 % of its flops special functions and a data-dependent walk.
  KernelRow r = counted_row(1e5, 0.01, 1000, 10);
  r.special_share = 0.4;
  r.walk = true;
  place_kernel_row(r, 400.0, 20.0, 2);
  EXPECT_DOUBLE_EQ(r.gflops, 10.0);
  EXPECT_NEAR(r.fraction, 0.025, 1e-15);
  EXPECT_NE(r.limit.find("transcendentals: 40.0%"), std::string::npos) << r.limit;
  EXPECT_NE(r.limit.find("walk"), std::string::npos) << r.limit;
  EXPECT_EQ(r.limit.find("memory"), std::string::npos) << r.limit;
  // the same row in 1 ms of device time in all, on a device of 1e6 compute units: launches, too few units
  KernelRow small = counted_row(1e3, 1e-3, 1000, 10);
  place_kernel_row(small, 1e6, 20.0, 1000000);
  EXPECT_NE(small.limit.find("launch overhead"), std::string::npos) << small.limit;
  EXPECT_NE(small.limit.find("too few work units"), std::string::npos) << small.limit;
}

TEST(KernelRoofline, UncountedRowHasThroughputOnly) {
  KernelRow r;
  r.units = 500;
  r.device_seconds = 0.5;
  place_kernel_row(r, 400.0, 20.0, 2);
  EXPECT_DOUBLE_EQ(r.units_per_second, 1000.0);
  EXPECT_EQ(r.gflops, 0.0);
  EXPECT_TRUE(r.bound.empty());
}

TEST(KernelRoofline, EveryCountHasUnitsAndItsFlopsAreTheSumOfTheirKinds) {
  // The generated table (host/src/report/kernel_ops.inc): what the report divides by.
  // Every row in both shapes but the strips (the CPU shape's quadrature: the GPU shape walks a texel a work-item).
  for (const std::string shape : {"cpu", "gpu"})
    for (const char* row : {"dfg_lut ggx fp32", "dfg_lut ggx fp64", "brdf_pairs disney fp32", "brdf_pairs disney fp64",
                            "brdf_grid disney fp32", "equirect_to_cube fp32", "prefilter_pyramid_strips fp32",
                            "prefilter_pyramid fp32", "prefilter_level fp32"}) {
      const KernelOpCount* c = find_kernel_op_count(row, shape);
      if (shape == "gpu" && std::string(row).find("strips") != std::string::npos) {
        EXPECT_EQ(c, nullptr) << row;
        continue;
      }
      ASSERT_NE(c, nullptr) << row << ": no count in the " << shape << " shape (scripts/count_kernel_ops.sh)";
      EXPECT_GT(c->units, 0.0) << row;
      EXPECT_GT(c->flops, 0.0) << row;
      EXPECT_GT(c->load_bytes + c->store_bytes, 0.0) << row;
      EXPECT_DOUBLE_EQ(c->add + c->mul + c->fma + c->div + c->sqrt + c->transcendental, c->flops) << row;
      const bool fp64 = std::string(row).find("fp64") != std::string::npos;
      if (fp64)
        EXPECT_GT(c->fp64_flops, 0.5 * c->flops) << row;
      else
        EXPECT_EQ(c->fp64_flops, 0.0) << row;
      EXPECT_EQ(std::string(c->source_hash).size(), 16u) << row;
    }
  EXPECT_EQ(find_kernel_op_count("no such row", "cpu"), nullptr);
}

TEST(KernelRoofline, PageAndJsonOfAnInjectedReport) {
  Report rep;
  rep.device = "test device";
  KernelsReport k;
  k.shape = "cpu";
  k.fp32 = {400.0, 0.02, 8e9};
  k.fp64 = {200.0, 0.02, 4e9};
  k.bandwidth = 20.0;
  k.rows.push_back(counted_row(1e5, 0.01, 1000, 10));
  k.rows.back().walk = true;
  place_kernel_row(k.rows.back(), 400.0, 20.0, 2);
  KernelRow uncounted;
  uncounted.id = uncounted.kernel = "other";
  uncounted.precision = "fp32";
  k.rows.push_back(uncounted);
  rep.kernels.push_back(k);
  rep.options.kinds = {"kernels"};
  const nlohmann::json j = nlohmann::json::parse(report_json(rep));
  ASSERT_TRUE(j.contains("kernels"));
  EXPECT_EQ(j["kernels"]["kernel_shape"], "cpu");
  EXPECT_DOUBLE_EQ(j["kernels"]["peaks"]["fp32_gflops"].get<double>(), 400.0);
  ASSERT_EQ(j["kernels"]["rows"].size(), 2u);
  EXPECT_DOUBLE_EQ(j["kernels"]["rows"][0]["gflops"].get<double>(), 10.0);
  EXPECT_DOUBLE_EQ(j["kernels"]["rows"][0]["fraction"].get<double>(), 0.025);
  EXPECT_FALSE(j["kernels"]["rows"][1]["counted"].get<bool>());
  const std::string html = report_html(rep);
  EXPECT_NE(html.find("where each kernel stands against its device"), std::string::npos);
  EXPECT_NE(html.find("roofline (cpu shape)"), std::string::npos);
  EXPECT_NE(html.find("Kernel shape <b>cpu</b>"), std::string::npos);
  EXPECT_NE(html.find("2.5%"), std::string::npos);
  EXPECT_NE(html.find("not counted in the cpu shape"), std::string::npos);
  EXPECT_EQ(html.find("http://"), html.find("http://www.w3.org/2000/svg"));  // nothing fetched
}

TEST(KernelRoofline, DevicePeakAndBandwidthKernelsGivePositiveFigures) {
  BRDFBAKE_REQUIRE_DEVICE(dev);
  const KernelsReport r = measure_device_peaks(*dev);
  EXPECT_EQ(r.shape, dev->info().kernel_shape);
  EXPECT_TRUE(std::isfinite(r.fp32.gflops));
  EXPECT_GT(r.fp32.gflops, 0.0);
  EXPECT_GT(r.fp32.seconds, 0.0);
  // the flops are exact: work-items x iterations x 8 chains x 16 lanes x 2, a whole number of 256s
  EXPECT_EQ(std::fmod(r.fp32.flops, 256.0), 0.0);
  EXPECT_DOUBLE_EQ(r.fp32.gflops, r.fp32.flops / r.fp32.seconds * 1e-9);
  if (dev->info().fp64) {
    EXPECT_GT(r.fp64.gflops, 0.0);
    EXPECT_EQ(std::fmod(r.fp64.flops, 256.0), 0.0);
  }
  EXPECT_GT(r.bandwidth, 0.0);
  EXPECT_GT(r.bandwidth_bytes, 0.0);
  EXPECT_EQ(std::fmod(r.bandwidth_bytes, 48.0), 0.0);  // 3 arrays of float4
}

}  // namespace
}  // namespace brdfbake
