// Forbidden: a library includes app. Must fail to compile (tests/CMakeLists.txt).
#include "app/report/charts.hpp"

int c2d_layer_probe() { return 0; }
