// Benchmark of the whole triangulation (strata::triangulate) on Data/gulf_section.vtp at
// three grid levels giving about 1e4, 1e5 and 1e6 triangles, with the default settings
// (BM_TriangulateGulfSection: the paper's method and the optimization beyond it) and with
// the paper's method alone (BM_TriangulateGulfSectionPaperMethod: Optimization off, the
// method issue 4 delivers). Counters: triangles, vertices, smallest angle, the boundary's
// largest deviation in local edges (MaxRelativeBoundaryDeviation), simulation steps,
// the seconds of each stage of the last run (s_<stage>) and the longest gap between two
// progress calls (the abort latency; the label names the stages of the two calls around it),
// (STRATAMESH_PRINT_GAPS=SECONDS prints every gap longer than that on stderr),
// and the machine's memory latency around the runs (memory_latency_ns: one dependent read at
// random in 64 MiB, the mean of a probe before the runs and one after; this machine's slow
// minutes are slow memory, see memoryLatency()).
// BM_TriangulatePickedHorizons: the default settings (automatic sizes) on a seismic line's
// picked horizons (pickedHorizons(): one pick per trace, tens of thousands of input points),
// for the stages' cost in the input's size rather than the mesh's.
// BM_AbortGulfSection: the time an abort asked N ms into a 1 M-triangle run takes to return.
// BM_TwoHalves: the cost of one strata::bothHalves() call
// with two empty halves, back to back or after a pause of the argument's microseconds (the
// second thread then asleep); BM_TwoHalvesThreadPerCall: a thread started and joined per call,
// as bothHalves did before 2026-12-05 (a 1 M-triangle run makes some 1400 such calls).
#include "Mesher.h"
#include "Parallel.h"
#include "VtpAscii.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <string>
#include <thread>
#include <utility>

namespace
{
const strata::RawPolylines& gulf()
{
  static const strata::RawPolylines raw =
    strata_test::readVtpAscii(strata_test::dataPath("gulf_section.vtp"));
  return raw;
}

// Nanoseconds per read of a chain of dependent reads at random in 64 MiB (one cycle through
// every slot, Sattolo's shuffle): the memory latency of the minute. On the machines of issue 4
// a 1 M-triangle run's seconds follow it, not the processor's speed (README, Speed and
// memory). The array is made once and kept, so that its memory, once freed, cannot make a
// later run's first writes cheaper.
double memoryLatency()
{
  constexpr std::size_t kSlots = (std::size_t(64) << 20) / sizeof(std::uint64_t);
  static const std::unique_ptr<std::uint64_t[]> next = []
  {
    std::unique_ptr<std::uint64_t[]> a(new std::uint64_t[kSlots]);
    for (std::size_t i = 0; i < kSlots; ++i)
    {
      a[i] = i;
    }
    std::uint64_t x = 88172645463325252ull; // (xorshift64)
    for (std::size_t i = kSlots - 1; i > 0; --i)
    {
      x ^= x << 13;
      x ^= x >> 7;
      x ^= x << 17;
      std::swap(a[i], a[x % i]); // j < i: one cycle
    }
    return a;
  }();
  constexpr int kReads = 1 << 20;
  std::uint64_t at = 0;
  const auto start = std::chrono::steady_clock::now();
  for (int k = 0; k < kReads; ++k)
  {
    at = next[at];
  }
  const double seconds =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  benchmark::DoNotOptimize(at);
  return 1e9 * seconds / kReads;
}

// A seismic line's horizons as picked, in the Shared curves form: `horizons` smooth layers
// (thickness varying by up to 80% along the line, at least 5% of the mean) across a section
// 20 km wide and 4 km deep, one pick per trace (12.5 m apart: 1601 per horizon), each off its
// smooth layer by a normal jitter of `jitter` metres (a seismic sample is a few metres), no layer
// thinner than 4 jitters; a top curve and the sides close the regions. Deterministic (xorshift64,
// Box-Muller).
strata::RawPolylines pickedHorizons(int horizons, double jitter)
{
  constexpr double kWidth = 20000.0, kDepth = 4000.0, kTrace = 12.5, kPi = 3.14159265358979323846;
  constexpr int kTraces = static_cast<int>(kWidth / kTrace) + 1;
  std::uint64_t seed = 0x9E3779B97F4A7C15ull + static_cast<std::uint64_t>(horizons);
  const auto uniform = [&]()
  {
    seed ^= seed << 13;
    seed ^= seed >> 7;
    seed ^= seed << 17;
    return (static_cast<double>(seed >> 11) + 0.5) / 9007199254740992.0; // (0, 1)
  };
  const auto normal = [&]()
  { return std::sqrt(-2.0 * std::log(uniform())) * std::cos(2.0 * kPi * uniform()); };
  const double mean = kDepth / (horizons + 1);
  std::vector<std::vector<double>> depth(1, std::vector<double>(kTraces, 0.0));
  std::vector<double> smooth(kTraces, 0.0);
  for (int k = 1; k <= horizons; ++k)
  {
    const double t = mean * (0.3 + 1.2 * uniform());
    const double waves = 0.5 + 3.5 * uniform(), phase = 6.0 * uniform();
    std::vector<double> y(kTraces);
    for (int i = 0; i < kTraces; ++i)
    {
      const double x = i * kTrace;
      smooth[i] +=
        std::max(t * (1.0 + 0.8 * std::sin(2.0 * kPi * waves * x / kWidth + phase)), 0.05 * t);
      y[i] = std::max(smooth[i] + jitter * normal(), depth.back()[i] + 4.0 * jitter);
    }
    depth.push_back(std::move(y));
  }
  std::vector<double> top(depth.back());
  for (double& y : top)
  {
    y += mean;
  }
  depth.push_back(std::move(top));
  strata::RawPolylines raw;
  raw.form = strata::ModelForm::SharedCurves;
  raw.offsets.push_back(0);
  const auto curve = [&](const std::vector<strata::Vec2>& points, int left, int right)
  {
    for (const strata::Vec2& p : points)
    {
      raw.connectivity.push_back(static_cast<std::int64_t>(raw.points.size()));
      raw.points.push_back(p);
    }
    raw.offsets.push_back(static_cast<std::int64_t>(raw.connectivity.size()));
    raw.leftRegion.push_back(left);
    raw.rightRegion.push_back(right);
  };
  const int curves = static_cast<int>(depth.size()); // regions 0 .. curves - 2, bottom up
  for (int k = 0; k < curves; ++k)
  {
    std::vector<strata::Vec2> line(kTraces);
    for (int i = 0; i < kTraces; ++i)
    {
      line[i] = { i * kTrace, depth[k][i] };
    }
    curve(line, k + 1 < curves ? k : -1, k - 1); // (walking east: the layer above on the left)
  }
  for (int k = 0; k + 1 < curves; ++k)
  {
    curve({ { 0.0, depth[k].front() }, { 0.0, depth[k + 1].front() } }, -1, k);
    curve({ { kWidth, depth[k].back() }, { kWidth, depth[k + 1].back() } }, k, -1);
  }
  return raw;
}

// Runs triangulate on `raw` as the benchmark's iterations and sets its counters.
void triangulateModel(benchmark::State& state,
  const strata::RawPolylines& raw,
  const strata::MesherParams& params)
{
  strata::MesherResult result;
  double longestGap = 0.0;
  std::string gapStage, lastStage; // the stage of the report that ended the longest gap
  const double latencyBefore = memoryLatency();
  // STRATAMESH_PRINT_GAPS=SECONDS: every gap between progress calls longer than that is
  // printed on stderr, with its end (steady_clock, seconds) and the stages around it.
  const char* printGapsText = std::getenv("STRATAMESH_PRINT_GAPS");
  const double printGaps =
    printGapsText ? std::atof(printGapsText) : std::numeric_limits<double>::infinity();
  for (auto _ : state)
  {
    auto previous = std::chrono::steady_clock::now();
    result = strata::triangulate(raw,
      params,
      [&](double, const char* stage)
      {
        const auto now = std::chrono::steady_clock::now();
        const double gap = std::chrono::duration<double>(now - previous).count();
        if (gap > printGaps)
        {
          // (steady_clock is CLOCK_MONOTONIC here: `perf record -k CLOCK_MONOTONIC` and
          // `perf script --time END-GAP,END` show what ran in the gap.)
          std::fprintf(stderr,
            "gap %.3f s ending at %.6f: %s -> %s\n",
            gap,
            std::chrono::duration<double>(now.time_since_epoch()).count(),
            lastStage.c_str(),
            stage);
        }
        if (gap > longestGap)
        {
          longestGap = gap;
          gapStage = (lastStage.empty() ? std::string() : lastStage + " -> ") + stage;
        }
        lastStage = stage;
        previous = now;
        return true;
      });
    benchmark::DoNotOptimize(result.triangles.data());
  }
  state.counters["triangles"] = static_cast<double>(result.summary.triangles);
  state.counters["vertices"] = static_cast<double>(result.summary.vertices);
  state.counters["min_angle"] = result.summary.minAngle;
  state.counters["boundary_local_edges"] = result.summary.maxRelativeDeviation;
  state.counters["iterations"] = result.summary.iterations;
  state.counters["s_total"] = result.summary.totalSeconds;
  state.counters["max_progress_gap_s"] = longestGap;
  state.counters["memory_latency_ns"] = 0.5 * (latencyBefore + memoryLatency());
  state.SetLabel("longest gap: " + gapStage);
  for (const auto& stage : result.summary.secondsPerStage)
  {
    std::string name = "s_" + stage.first;
    std::replace(name.begin(), name.end(), ' ', '_');
    state.counters[name] = stage.second;
  }
}

void triangulateGulfSection(benchmark::State& state, bool optimize)
{
  strata::MesherParams params;
  params.grid.maxLevel = static_cast<int>(state.range(0));
  params.compression.optimize = optimize;
  triangulateModel(state, gulf(), params);
}

void BM_TriangulateGulfSection(benchmark::State& state)
{
  triangulateGulfSection(state, true);
}

void BM_TriangulateGulfSectionPaperMethod(benchmark::State& state)
{
  triangulateGulfSection(state, false);
}

// The arguments: the number of horizons (the input points: 1601 per horizon and curve) and the
// picks' jitter in decimetres.
void BM_TriangulatePickedHorizons(benchmark::State& state)
{
  const strata::RawPolylines raw =
    pickedHorizons(static_cast<int>(state.range(0)), 0.1 * static_cast<double>(state.range(1)));
  state.counters["input_points"] = static_cast<double>(raw.points.size());
  triangulateModel(state, raw, strata::MesherParams());
}

// An abort asked the argument's milliseconds into a 1 M-triangle run (default settings), as a
// user's click would be: the callback returns false from its first call at or after that
// moment. abort_latency_s is the time from that moment to triangulate's return (strata::
// Aborted): the wait for the next progress report plus the unwinding, background tasks
// joined. The label names the stage the abort met.
void BM_AbortGulfSection(benchmark::State& state)
{
  strata::MesherParams params;
  params.grid.maxLevel = 24;
  const auto after = std::chrono::milliseconds(state.range(0));
  double latency = -1.0;
  std::string met = "(finished first)";
  for (auto _ : state)
  {
    const auto start = std::chrono::steady_clock::now();
    bool asked = false;
    try
    {
      strata::triangulate(gulf(),
        params,
        [&](double, const char* stage)
        {
          if (!asked && std::chrono::steady_clock::now() - start >= after)
          {
            asked = true;
            met = stage;
          }
          return !asked;
        });
    }
    catch (const strata::Aborted&)
    {
    }
    const auto end = std::chrono::steady_clock::now();
    latency = asked ? std::chrono::duration<double>(end - (start + after)).count() : -1.0;
  }
  state.counters["abort_latency_s"] = latency;
  state.SetLabel(met);
}

// Each call timed on its own (manual time), after the pause.
template<class Call>
void timeCalls(benchmark::State& state, Call&& call)
{
  const auto pause = std::chrono::microseconds(state.range(0));
  for (auto _ : state)
  {
    if (pause.count() > 0)
    {
      std::this_thread::sleep_for(pause);
    }
    const auto start = std::chrono::steady_clock::now();
    call();
    state.SetIterationTime(
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
}

void BM_TwoHalves(benchmark::State& state)
{
  int halves[2] = { 0, 0 };
  timeCalls(state, [&] { strata::bothHalves([&] { ++halves[0]; }, [&] { ++halves[1]; }); });
  benchmark::DoNotOptimize(halves);
}

void BM_TwoHalvesThreadPerCall(benchmark::State& state)
{
  int halves[2] = { 0, 0 };
  timeCalls(state,
    [&]
    {
      std::thread other([&] { ++halves[1]; });
      ++halves[0];
      other.join();
    });
  benchmark::DoNotOptimize(halves);
}
} // namespace

// maxLevel 10: ~1e4 triangles, 18: ~1e5, 24: ~1e6.
BENCHMARK(BM_TriangulateGulfSection)->Arg(10)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TriangulateGulfSection)->Arg(18)->Iterations(3)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TriangulateGulfSection)->Arg(24)->Iterations(1)->Unit(benchmark::kMillisecond);
// The paper's method alone: the same levels give 1.0e4, 1.1e5 and 1.0e6 triangles.
BENCHMARK(BM_TriangulateGulfSectionPaperMethod)->Arg(10)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TriangulateGulfSectionPaperMethod)
  ->Arg(18)
  ->Iterations(3)
  ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TriangulateGulfSectionPaperMethod)
  ->Arg(24)
  ->Iterations(1)
  ->Unit(benchmark::kMillisecond);
// 10 and 30 horizons (19 k and 51 k input points) picked within 1 m; 30 within 2.5 m (a seismic
// sample's jitter: the mesh resolves it, and ThinLayerRetry makes it again finer: about 110 s).
BENCHMARK(BM_TriangulatePickedHorizons)
  ->Args({ 10, 10 })
  ->Args({ 30, 10 })
  ->Args({ 30, 25 })
  ->Iterations(1)
  ->Unit(benchmark::kMillisecond);

// Back to back, and 1 ms apart.
BENCHMARK(BM_AbortGulfSection)
  ->DenseRange(100, 4300, 300)
  ->Iterations(1)
  ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TwoHalves)->Arg(0)->Arg(1000)->UseManualTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_TwoHalvesThreadPerCall)
  ->Arg(0)
  ->Arg(1000)
  ->UseManualTime()
  ->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
