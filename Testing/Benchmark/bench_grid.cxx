// Benchmark of the adaptive 4-8 grid and its classification on Data/gulf_section.vtp, at about
// 1e5, 1e6 and 4e6 leaf triangles (one core).
//
//   bench_grid --benchmark_min_time=0.1
//
// Counters: leaves (actual triangle count), grid_MB and bytes_per_leaf (Grid48::memoryBytes(),
// the capacity of all the grid's arrays, hierarchy included, over the leaf count), and
// peak_MB, the process's peak resident memory (VmHWM) during the case, reset before it through
// /proc/self/clear_refs (0 where that is not available).
#include "Classification.h"
#include "DistanceField.h"
#include "Grid48.h"
#include "VtpAscii.h"

#include <benchmark/benchmark.h>

#include <fstream>
#include <memory>
#include <string>

namespace
{

struct Loaded
{
  strata::Model model;
  std::unique_ptr<strata::DistanceField> field;
};

const Loaded& gulf()
{
  static const std::unique_ptr<Loaded> loaded = []
  {
    auto l = std::make_unique<Loaded>();
    l->model =
      strata::buildModel(strata_test::readVtpAscii(strata_test::dataPath("gulf_section.vtp")));
    l->field = std::make_unique<strata::DistanceField>(l->model);
    return l;
  }();
  return *loaded;
}

// (maxLevel, localMaxLevel) for about 1e5, 1e6 and 4e6 leaves on gulf_section.vtp.
struct Size
{
  int maxLevel;
  int localMaxLevel;
};
const Size kSizes[] = { { 17, 21 }, { 24, 28 }, { 28, 32 } };

strata::Grid48Params paramsOf(const benchmark::State& state)
{
  strata::Grid48Params p;
  p.maxLevel = kSizes[state.range(0)].maxLevel;
  p.localMaxLevel = kSizes[state.range(0)].localMaxLevel;
  return p;
}

// Resets the peak resident memory (Linux: "5" to clear_refs).
void resetPeak()
{
  std::ofstream("/proc/self/clear_refs") << "5";
}

// Peak resident memory in MB since the last reset, 0 when unknown.
double peakMB()
{
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
  {
    if (line.rfind("VmHWM:", 0) == 0)
    {
      return std::stod(line.substr(6)) / 1024.0; // kB
    }
  }
  return 0.0;
}

void setCounters(benchmark::State& state, const strata::Grid48& grid, double peak)
{
  const double leaves = static_cast<double>(grid.numberOfLeaves());
  state.counters["leaves"] = leaves;
  state.counters["grid_MB"] = static_cast<double>(grid.memoryBytes()) / (1024.0 * 1024.0);
  state.counters["bytes_per_leaf"] = static_cast<double>(grid.memoryBytes()) / leaves;
  state.counters["peak_MB"] = peak;
}

void BM_Build(benchmark::State& state)
{
  const Loaded& m = gulf();
  const strata::Grid48Params p = paramsOf(state);
  resetPeak();
  std::unique_ptr<strata::Grid48> last;
  for (auto _ : state)
  {
    last.reset(); // one grid at a time
    last = std::make_unique<strata::Grid48>(strata::Grid48::build(m.model, *m.field, p));
    benchmark::DoNotOptimize(last->numberOfLeaves());
  }
  setCounters(state, *last, peakMB());
}

void BM_BuildAndClassify(benchmark::State& state)
{
  const Loaded& m = gulf();
  const strata::Grid48Params p = paramsOf(state);
  resetPeak();
  std::unique_ptr<strata::Grid48> last;
  for (auto _ : state)
  {
    last.reset();
    last = std::make_unique<strata::Grid48>(strata::Grid48::build(m.model, *m.field, p));
    const strata::TriangleMesh mesh = last->extract();
    const strata::Classification c = strata::classify(mesh, m.model, *m.field);
    benchmark::DoNotOptimize(c.edgeClass.data());
  }
  setCounters(state, *last, peakMB());
}

// Classification alone (extract + classify of a grid built once, outside the timing).
void BM_Classify(benchmark::State& state)
{
  const Loaded& m = gulf();
  const strata::Grid48 grid = strata::Grid48::build(m.model, *m.field, paramsOf(state));
  std::size_t queries = 0;
  for (auto _ : state)
  {
    const strata::TriangleMesh mesh = grid.extract();
    const strata::Classification c = strata::classify(mesh, m.model, *m.field);
    queries = c.regionQueries;
    benchmark::DoNotOptimize(c.edgeClass.data());
  }
  state.counters["leaves"] = static_cast<double>(grid.numberOfLeaves());
  state.counters["region_queries"] = static_cast<double>(queries);
}

} // namespace

BENCHMARK(BM_Build)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BuildAndClassify)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Classify)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
