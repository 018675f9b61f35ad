// The DFG tables' former header name: brdfbake/dfg_lut.hpp, kept so that existing code compiles.
#include "brdfbake/dfg_lut.hpp"  // IWYU pragma: export
