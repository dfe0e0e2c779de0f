#include <stcosim/backend.hpp>

namespace st::cosim {

const char* toString(BackendKind k) {
  switch (k) {
    case BackendKind::Libsumo: return "libsumo";
    case BackendKind::Traci: return "libtraci";
  }
  return "?";
}

void Backend::step() {
  advance();
  read();
}

}  // namespace st::cosim
