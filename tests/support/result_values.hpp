// Every value a bake's result holds, in one list (tables, cube levels, SH and irradiance cubes, MERL
// tables, evaluated pairs): what the tests that compare two backends' results hold to a bound.
#pragma once

#include <vector>

#include "brdfbake/tables.hpp"

namespace brdfbake::test {

inline std::vector<double> values_of(const BakeResult& r) {
  std::vector<double> v;
  auto add = [&](const auto& list) { v.insert(v.end(), list.begin(), list.end()); };
  if (const Table* t = r.table()) add(t->data);
  if (const CubeLevels* c = r.cube())
    for (const auto& level : c->levels) add(level);
  if (const IrradianceResult* i = r.irradiance()) {
    add(i->sh.radiance);
    for (const auto& level : i->cube.levels) add(level);
  }
  if (const MerlTable* m = r.merl()) add(m->values);
  if (const EvalResult* e = r.eval()) add(e->values);
  return v;
}

}  // namespace brdfbake::test
