// Forbidden: core includes constraints. Must fail to compile (tests/CMakeLists.txt).
#include "constraints/contact_set.hpp"

int c2d_layer_probe() { return 0; }
