// Named tolerances of the test suite, each with the reason for its size.
#pragma once

namespace brdfbake::test {

// The reference integrals are stated converged to 1e-6 absolute; comparisons between two
// reference evaluations by different routes (identities) allow twice that.
inline constexpr double kReferenceConverged = 2e-6;

}  // namespace brdfbake::test
