// Internal: the DFG table Filament samples (docs/ENGINES.md, "Filament (`filament`)"). Filament never
// reads a bake's DFG table: every material samples the table built into the library (light_iblDFG),
// which Filament's build makes with its own cmgen (filament/CMakeLists.txt: `cmgen --size=128
// --ibl-dfg-multiscatter --ibl-dfg-cloth`) and ships as half floats. This is that table, computed as
// google/filament libs/ibl/src/CubemapIBL.cpp's DFG does:
//   - 128 x 128 texels; column s holds NoV = (s + 0.5) / 128; texture row t holds perceptual roughness
//     min(1, (t + 1.5) / 128) (cmgen's iblLutDfg: coord = saturate((h - y + 0.5) / h) for image row y,
//     written bottom-up, y = 127 - t), linear roughness its square;
//   - x = 4/N sum V NoL VoH/NoH (1 - VoH)^5, y = 4/N sum V NoL VoH/NoH over N = 1024 Hammersley points
//     importance-sampled from GGX (DFV_Multiscatter; V the height-correlated Smith visibility);
//   - z = 8 pi/N sum V_Ashikhmin D_Charlie NoL VoH over N = 4096 uniform Hammersley points (DFV_Charlie_Uniform);
//   - every value rounded to binary16, as the shipped RGB16F texture holds it.
// The shader samples it bilinearly, clamp to edge, at (NoV, perceptualRoughness): specularDFG =
// mix(x, y, f0), energy compensation 1 + f0 (1 / y - 1), sheenDFG = z (light_indirect.fs).
// Checked against the table extracted from Filament 1.76 in the open3d-cpu 0.20.0 wheel
// (tests/python/test_engine_filament.py): every value within one binary16 step.
#pragma once

#include "brdfbake/table.hpp"

namespace brdfbake::detail {

inline constexpr int kFilamentDfgSize = 128;

// Channels "bias" (x), "albedo" (y), "charlie" (z); x, y the texture's columns and rows (n_dot_v and
// perceptual roughness at texel centres, as the lookup takes them). Computed once a process, then shared:
// 1.7 s of CPU (84 M samples in double), on every core (0.9 s on 2).
const Table& filament_dfg_table();

}  // namespace brdfbake::detail
