// Micro-benchmarks (Google Benchmark): element kernels, sparse assembly (pattern and refill),
// the direct solve, and contact detection, on structured meshes of growing size. Figures, not
// assertions: `build/bench/c2d_micro_bench` prints them; `contact2d bench` covers whole runs.
#include <benchmark/benchmark.h>

#include <cmath>

#include "constraints/contact_detection.hpp"
#include "core/assembler.hpp"
#include "core/dof_map.hpp"
#include "core/elasticity_kernels.hpp"
#include "core/fill_ordering.hpp"
#include "core/material.hpp"
#include "core/mesh.hpp"
#include "core/spd_solver.hpp"
#include "core/structured_grid.hpp"

using namespace c2d;
using namespace c2d::core;

namespace {

using Grid = StructuredGrid;
Grid make_grid(int n, int order) { return make_structured_grid(n, order); }

void kernel(benchmark::State& state, int order) {
  const Grid g = make_grid(4, order);
  double sink = 0;
  for (auto _ : state) {
    for (int e = 0; e < g.mesh.num_elements(); ++e) sink += element_stiffness(g.mesh.element_coords(e), g.material)(0, 0);
  }
  benchmark::DoNotOptimize(sink);
  state.SetItemsProcessed(state.iterations() * g.mesh.num_elements());
}
void BM_KernelT3(benchmark::State& s) { kernel(s, 1); }
void BM_KernelT6(benchmark::State& s) { kernel(s, 2); }

void pattern(benchmark::State& state, int order) {
  const Grid g = make_grid(static_cast<int>(state.range(0)), order);
  for (auto _ : state) {
    Assembler a(g.mesh, g.dofs);
    benchmark::DoNotOptimize(a.matrix().nonZeros());
  }
  state.SetItemsProcessed(state.iterations() * g.mesh.num_elements());
  state.counters["dofs"] = g.mesh.num_dofs();
}
void BM_PatternT3(benchmark::State& s) { pattern(s, 1); }
void BM_PatternT6(benchmark::State& s) { pattern(s, 2); }

void refill(benchmark::State& state, int order, int threads = 1) {
  const Grid g = make_grid(static_cast<int>(state.range(0)), order);
  Assembler a(g.mesh, g.dofs);
  a.set_threads(threads);
  for (auto _ : state) {
    a.assemble([&](int e, LocalMatrix& ke) { ke = element_stiffness(g.mesh.element_coords(e), g.material); },
               nullptr, nullptr);
    benchmark::DoNotOptimize(a.matrix().valuePtr());
  }
  state.SetItemsProcessed(state.iterations() * g.mesh.num_elements());
  state.counters["dofs"] = g.mesh.num_dofs();
}
void BM_AssembleT3(benchmark::State& s) { refill(s, 1); }
void BM_AssembleT6(benchmark::State& s) { refill(s, 2); }
void BM_AssembleT3TwoThreads(benchmark::State& s) { refill(s, 1, 2); }
void BM_AssembleT6TwoThreads(benchmark::State& s) { refill(s, 2, 2); }

/// One analysis, factorisation and solve of a T6 grid; `corner`: the mesh's corner-graph order
/// (core/fill_ordering.hpp), else CHOLMOD's AMD on the matrix; `split`: with its two-way split
/// (two threads, if OpenMP offers them).
void factorize_solve(benchmark::State& state, bool corner, bool split = false) {
  const Grid g = make_grid(static_cast<int>(state.range(0)), 2);
  Assembler a(g.mesh, g.dofs);
  a.assemble([&](int e, LocalMatrix& ke) { ke = element_stiffness(g.mesh.element_coords(e), g.material); },
             nullptr, nullptr);
  const VecX b = VecX::Ones(g.dofs.num_free());
  for (auto _ : state) {
    SpdSolver solver;
    if (corner)
      solver.set_ordering(std::make_shared<const FillOrder>(
                              split ? mesh_fill_order(g.mesh, g.dofs)
                                    : FillOrder{corner_graph_ordering(g.mesh, g.dofs), {}, {}}),
                          "corner_amd");
    solver.factorize(a.matrix());
    VecX x;
    solver.solve(b, x);
    state.counters["symbolic_s"] = solver.report().symbolic_seconds;
    state.counters["numeric_s"] = solver.report().numeric_seconds;
    state.counters["fill"] = solver.report().factor_nonzeros / a.matrix().nonZeros();
  }
  state.counters["dofs"] = g.mesh.num_dofs();
}
void BM_FactorizeSolveT6(benchmark::State& s) { factorize_solve(s, false); }
void BM_FactorizeSolveT6CornerOrder(benchmark::State& s) { factorize_solve(s, true); }
void BM_FactorizeSolveT6Split(benchmark::State& s) { factorize_solve(s, true, true); }

void BM_Detection(benchmark::State& state) {
  // A master polyline of n edges along y = 0 and n slave points just above it.
  const int n = static_cast<int>(state.range(0));
  std::vector<Vec2> x;
  std::vector<constraints::MasterEdge> edges;
  for (int i = 0; i <= n; ++i) x.emplace_back(static_cast<double>(i) / n, 0.0);
  for (int i = 0; i < n; ++i) {
    constraints::MasterEdge e;
    e.nodes = {i + 1, i, -1};  // outward normal +y
    edges.push_back(e);
  }
  const int first_slave = static_cast<int>(x.size());
  for (int i = 0; i < n; ++i) x.emplace_back((i + 0.37) / n, 0.1 / n);
  const constraints::MasterSurfaceSearch search(edges, x, 2.0 / n);
  for (auto _ : state) {
    double sink = 0;
    for (int i = 0; i < n; ++i) sink += search.project(x[first_slave + i]).gap;
    benchmark::DoNotOptimize(sink);
  }
  state.SetItemsProcessed(state.iterations() * n);
}

}  // namespace

BENCHMARK(BM_KernelT3);
BENCHMARK(BM_KernelT6);
BENCHMARK(BM_PatternT3)->Arg(100)->Arg(300)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PatternT6)->Arg(50)->Arg(150)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AssembleT3)->Arg(100)->Arg(300)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AssembleT6)->Arg(50)->Arg(150)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AssembleT3TwoThreads)->Arg(300)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_AssembleT6TwoThreads)->Arg(150)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_FactorizeSolveT6)->Arg(50)->Arg(150)->Arg(350)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_FactorizeSolveT6CornerOrder)->Arg(50)->Arg(150)->Arg(350)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_FactorizeSolveT6Split)->Arg(50)->Arg(150)->Arg(350)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_Detection)->Arg(1000)->Arg(100000)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
