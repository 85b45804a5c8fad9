#include <cstdio>

#include "app.hpp"

namespace statepack::path_tracer {
int run_windowed(const Options&) {
  std::fprintf(stderr, "path_tracer: the window mode is not built yet; use --headless\n");
  return 2;
}
}  // namespace statepack::path_tracer
