// Internal: what the device path (dfg_lut.cpp) and the reference backend
// (reference_backend/dfg_lut.cpp) of the DFG tables share.
#pragma once

#include "brdfbake/lut.hpp"
#include "brdfbake/table.hpp"

namespace brdfbake::detail {

// The table of a resolved spec (resolve_lut_spec): axes, channels and the metadata every DFG table
// carries; the backend fills the data and adds its device, precision, estimator and error bound.
Table make_lut_table(const LutSpec& resolved);

}  // namespace brdfbake::detail
