// Forbidden: core includes nonlinear. Must fail to compile (tests/CMakeLists.txt).
#include "nonlinear/load_stepper.hpp"

int c2d_layer_probe() { return 0; }
