// Reader for the data files of the seed thesis program (its GetInput routine).
//
// Format (whitespace separated, one record per line):
//   NN NE ITER
//   NN node lines:    id x y sx sy fx fy       sx/sy = 1: DOF supported, and then fx/fy is
//                                              its prescribed displacement (the program added
//                                              BIG to the diagonal and BIG*value to the RHS);
//                                              sx/sy = 0: fx/fy is a nodal force
//   NE element lines: id n1 n2 n3 [n4 n5 n6] type p1 p2 p3
//                     type 0: plane stress, p = (E, thickness, nu)
//                     type 2: plane strain, p = (E, thickness, nu)
//                     type 1: node-to-node gap element n1-n2, p = (nx, ny, k)
//   BIG BIGkr        the two "big numbers" (read and ignored: supports are eliminated)
// T3 or T6 is inferred from the number of fields of the element lines (8 or 11).
#pragma once

#include <string>

#include "core/scene.hpp"

namespace c2d::core {

/// Reads a legacy data file into a Scene with an explicit mesh. Throws InputError naming the
/// file and line. Gap elements are kept in Scene::explicit_model->gaps.
Scene read_legacy_scene(const std::string& path);

}  // namespace c2d::core
