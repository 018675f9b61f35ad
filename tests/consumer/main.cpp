// A program built against the installed brdfbake: bakes a small DFG table on the default device
// (or the reference when BRDFBAKE_CONSUMER_REFERENCE is set) and prints one texel.
#include <cstdio>
#include <cstdlib>

#include "brdfbake/backend.hpp"
#include "brdfbake/tables.hpp"
#include "brdfbake/version.hpp"

int main() {
  try {
    brdfbake::TableRequest t;
    t.kind = brdfbake::TableKind::Ggx;
    t.params = {{"size", 4.0}};
    brdfbake::validate_table(t);
    auto backend = brdfbake::Backend::open(std::getenv("BRDFBAKE_CONSUMER_REFERENCE") ? "reference" : "");
    const brdfbake::BakeResult r = brdfbake::bake_table(t, *backend);
    std::printf("brdfbake %s %s scale(3,3) %.6f\n", brdfbake::kVersion, t.output.c_str(), r.table()->at(3, 3, 0));
    return 0;
  } catch (const brdfbake::Error& e) {
    std::fprintf(stderr, "consumer: %s\n", e.what());
    return 1;
  }
}
