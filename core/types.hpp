// Common numeric types of contact2d.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <cmath>
#include <vector>

namespace c2d {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using VecX = Eigen::VectorXd;
using SpMat = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
using Triplet = Eigen::Triplet<double, int>;

/// Dense local element matrix/vector with a fixed upper bound (T6: 12 DOFs), so element loops
/// never touch the heap.
constexpr int kMaxElementDofs = 12;
using LocalMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor,
                                  kMaxElementDofs, kMaxElementDofs>;
using LocalVector = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kMaxElementDofs, 1>;

/// Below this many elements the element loops (assembly, stress recovery, error estimate) run
/// on one thread: waking a second OpenMP thread beside OpenBLAS's spinning ones cost more than
/// it saved (a 3,160-element T6 assembly: 12 ms on one thread, 46 ms on two).
constexpr int kMinParallelElements = 20000;

/// The angle between two vectors, in [0, π] (atan2 of |a × b| and a · b: accurate near 0 and
/// π, where acos is not).
inline double angle_between(const Vec2& a, const Vec2& b) {
  return std::atan2(std::abs(a.x() * b.y() - a.y() * b.x()), a.dot(b));
}

/// Voigt stress or strain [xx, yy, xy] (engineering shear strain for strains).
using Voigt = Eigen::Vector3d;

}  // namespace c2d
