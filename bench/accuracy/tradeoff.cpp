// The speed/accuracy trade, measured: integrator x dt x wheel fidelity over
// scenes with analytic answers and the report's four experiments against a
// reference run, the stability map at the extremes, and an hour of
// simulated time. Writes CSV, PNG plots and docs/accuracy.md.
//
// The sedan's manoeuvres (road_scenes.hpp) against a converged reference.
//
//   tradeoff [--quick] [--road-only] [--jobs N] [--out DIR] [--docs FILE] [--img DIR]
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>

#include <CLI/CLI.hpp>

#include "physics/build/model_builder.hpp"
#include "report.hpp"

using namespace groundsim;
using namespace groundsim::accuracy;

namespace {

std::vector<Setting> settingsGrid(bool quick) {
  std::vector<Setting> out;
  auto add = [&](IntegratorKind k, std::vector<double> dts) {
    for (double dt : dts) out.push_back({k, dt, 1e-6, Fidelity::Rim20});
  };
  if (quick) {
    add(IntegratorKind::SemiImplicitEuler, {1e-4, 1e-3});
    add(IntegratorKind::Rk4, {1e-3});
    add(IntegratorKind::ImplicitEuler, {2e-3});
    out.push_back({IntegratorKind::Adaptive, 1e-2, 1e-4, Fidelity::Rim20});
    return out;
  }
  add(IntegratorKind::SemiImplicitEuler, {5e-5, 1e-4, 2e-4, 4e-4, 1e-3, 2e-3});
  add(IntegratorKind::VelocityVerlet, {1e-4, 2e-4, 4e-4, 1e-3, 2e-3});
  add(IntegratorKind::Rk4, {1e-4, 2e-4, 5e-4, 1e-3, 2e-3});
  add(IntegratorKind::ImplicitEuler, {1e-3, 2e-3, 5e-3});
  for (double tol : {1e-3, 1e-4, 1e-5, 1e-6}) out.push_back({IntegratorKind::Adaptive, 1e-2, tol, Fidelity::Rim20});
  return out;
}

// Runs tasks on `jobs` threads; each writes its own slot.
template <class F>
void parallelFor(size_t n, int jobs, F f) {
  std::atomic<size_t> next{0};
  std::vector<std::thread> pool;
  for (int j = 0; j < std::max(1, jobs); ++j)
    pool.emplace_back([&] {
      for (size_t i = next++; i < n; i = next++) f(i);
    });
  for (auto& t : pool) t.join();
}

// An hour of simulated time at one setting: the plain coast (energy must not
// grow, the car keeps rolling straight) or parked on 20 degrees (no creep).
HourRun hour(const std::string& scene, const Setting& s) {
  HourRun h;
  h.scene = scene;
  h.setting = s.label() + " " + fidelityName(s.fidelity);
  Options o = s.apply(Options{});
  o.contact.damping = 20.0;
  o.contact.friction = scene == "parked_20" ? 0.9 : 0.5;
  CarPlacement at;
  GroundPtr g;
  if (scene == "parked_20") {
    g = makeIncline(20 * std::numbers::pi / 180, Vec3::UnitX());
  } else {
    g = makePlane(Vec3::UnitZ(), 0);
    at.wheel_spin = 5.0;
  }
  ModelBuilder b(o, g);
  addCar(b, "car", carParams(s.fidelity), at);
  auto built = b.build();
  Simulator sim(built.model, built.initial);
  if (scene == "parked_20")
    for (auto& c : sim.controls()) c.brake_torque = 10.0;
  Result r;
  runTo(sim, 10.0, r);
  const Vec3 x10 = bodyPos(sim.state().y, 0);
  const double v10 = bodyVel(sim.state().y, 0).norm();
  runTo(sim, 3600.0, r);
  h.healthy = r.healthy;
  h.status = r.status;
  h.wall_seconds = r.wall_seconds;
  h.sim_per_wall = r.simPerWall();
  char buf[200];
  if (scene == "parked_20")
    std::snprintf(buf, sizeof buf, "creep from 10 s to 1 h: %.2e m", (bodyPos(sim.state().y, 0) - x10).norm());
  else
    std::snprintf(buf, sizeof buf, "speed %.4f m/s at 10 s, %.4f m/s at 1 h (rolling friction-free: should hold)",
                  v10, bodyVel(sim.state().y, 0).norm());
  h.outcome = buf;
  return h;
}

// The command line.
struct Args {
  bool quick = false;
  int jobs = 2;
  std::string out = "bench-accuracy-out", docs = "docs/accuracy.md", img = "docs/img";
  bool road_only = false;
  std::string configs = GROUNDSIM_CONFIGS;
};

void addOptions(CLI::App& app, Args& a) {
  app.add_flag("--quick", a.quick, "small grids (smoke test, about a minute)");
  app.add_flag("--road-only", a.road_only, "only the sedan's manoeuvres (prints their cells and the stick-slip section; writes no docs)");
  app.add_option("--configs", a.configs, "directory of sedan.json and sedan_hills.json");
  app.add_option("--jobs", a.jobs, "worker threads");
  app.add_option("--out", a.out, "directory for CSV and gnuplot files");
  app.add_option("--docs", a.docs, "markdown document to write");
  app.add_option("--img", a.img, "directory for the PNG plots");
}

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// --- 0. the sedan's manoeuvres ---------------------------------------------

struct RoadTask { size_t m; Setting s; bool stick = false; };

// Every manoeuvre's references first (RK4 at kRoadRefDt and at twice that,
// for the convergence; then the stick-slip tyre's own, Verlet), then every
// setting of either tyre against them.
struct RoadPlan {
  std::vector<RoadTask> tasks;
  size_t stick_refs = 0;  // where the stick-slip tyre's references start
  size_t cells = 0;       // where the settings start
};

RoadPlan roadPlan(size_t manoeuvres, bool quick) {
  RoadPlan p;
  auto& rt = p.tasks;
  for (size_t m = 0; m < manoeuvres; ++m) {
    rt.push_back({m, Setting{IntegratorKind::Rk4, kRoadRefDt, 1e-6, Fidelity::Circle}});
    rt.push_back({m, Setting{IntegratorKind::Rk4, 2 * kRoadRefDt, 1e-6, Fidelity::Circle}});
  }
  // the stick-slip tyre: its own references (Verlet), then its grid
  p.stick_refs = rt.size();
  for (size_t m = 0; m < manoeuvres; ++m) {
    rt.push_back({m, Setting{IntegratorKind::VelocityVerlet, kStickRefDt, 1e-6, Fidelity::Circle}, true});
    rt.push_back({m, Setting{IntegratorKind::VelocityVerlet, 2 * kStickRefDt, 1e-6, Fidelity::Circle}, true});
  }
  p.cells = rt.size();
  for (size_t m = 0; m < manoeuvres; ++m)
    for (const Setting& s : roadSettings(quick)) rt.push_back({m, s});
  for (size_t m = 0; m < manoeuvres; ++m)
    for (const Setting& s : stickSlipSettings(quick)) rt.push_back({m, s, true});
  return p;
}

// Runs the plan's tasks, longest first (hill road, small steps), so the
// threads end together; each run in its task's slot.
std::vector<RoadRun> runRoadPlan(const RoadPlan& plan, const std::vector<RoadManoeuvre>& ms,
                                 const std::string& configs, int jobs) {
  const auto& rt = plan.tasks;
  std::vector<RoadRun> runs(rt.size());
  std::fprintf(stderr, "sedan manoeuvres: %zu runs on %d threads\n", rt.size(), jobs);
  std::vector<size_t> order(rt.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return ms[rt[a].m].duration / rt[a].s.dt > ms[rt[b].m].duration / rt[b].s.dt;
  });
  parallelFor(rt.size(), jobs, [&](size_t k) {
    const size_t i = order[k];
    runs[i] = runRoad(ms[rt[i].m], rt[i].s, configs, rt[i].stick);
  });
  return runs;
}

// The references' convergence (2 dt against dt), then every setting's run
// against the reference of its tyre, into the report.
void collectRoad(const RoadPlan& plan, size_t manoeuvres, std::vector<RoadRun>& runs, Report& rep) {
  const auto& rt = plan.tasks;
  for (size_t m = 0; m < manoeuvres; ++m) {
    RoadReference ref{runs[2 * m], runs[2 * m + 1]};
    compareRoad(ref.half, ref.run);
    rep.road_refs.push_back(ref);
  }
  for (size_t m = 0; m < manoeuvres; ++m) {
    RoadReference ref{runs[plan.stick_refs + 2 * m], runs[plan.stick_refs + 2 * m + 1]};
    compareRoad(ref.half, ref.run);
    rep.stick_refs.push_back(ref);
  }
  for (size_t i = plan.cells; i < rt.size(); ++i) {
    compareRoad(runs[i], (rt[i].stick ? rep.stick_refs : rep.road_refs)[rt[i].m].run);
    (rt[i].stick ? rep.stick : rep.road).push_back(runs[i]);
  }
}

void sweepRoad(Report& rep, const Args& a) {
  const auto road_start = std::chrono::steady_clock::now();
  const auto& ms = roadManoeuvres();
  const RoadPlan plan = roadPlan(ms.size(), a.quick);
  std::vector<RoadRun> runs = runRoadPlan(plan, ms, a.configs, a.jobs);
  collectRoad(plan, ms.size(), runs, rep);
  rep.road_wall_seconds = secondsSince(road_start);
  std::fprintf(stderr, "sedan manoeuvres done in %.0f s\n", rep.road_wall_seconds);
}

// --road-only: the references, every cell and the stick-slip section on
// stdout, and road.csv.
void printRoad(const Report& rep, const std::string& out) {
  for (const RoadReference& r : rep.road_refs)
    std::printf("%-12s ref key %.6g length %.1f  2dt-vs-dt path max %.2e rms %.2e key %.2e %s\n",
                r.run.manoeuvre.c_str(), r.run.key, r.run.length, r.half.path_max, r.half.path_rms,
                r.half.key_error, r.run.status.c_str());
  for (const RoadReference& r : rep.stick_refs)
    std::printf("%-12s stick_slip ref key %.6g length %.1f  2dt-vs-dt path max %.2e rms %.2e key %.2e %s\n",
                r.run.manoeuvre.c_str(), r.run.key, r.run.length, r.half.path_max, r.half.path_rms,
                r.half.key_error, r.run.status.c_str());
  for (const auto* runs_of : {&rep.road, &rep.stick})
    for (const RoadRun& r : *runs_of)
      std::printf("%-12s %-13s %-28s %-10s max %.2e rms %.2e key %.6g (%.2e) evals/s %.0f sim/wall %.0f\n",
                  r.manoeuvre.c_str(), r.stick_slip ? "stick_slip" : "magic_formula", r.setting.label().c_str(),
                  r.status.c_str(), r.path_max, r.path_rms, r.key, r.key_error, r.evalsPerSim(), r.simPerWall());
  std::ostringstream md;
  writeStickSlipMarkdown(rep, md);
  std::printf("%s", md.str().c_str());
  writeRoadCsv(rep, out + "/road.csv");
}

// --- 1. the sweep: every scene x setting (x fidelity for car scenes) -------

struct Task { const Scene* scene; Setting setting; };

bool isExperiment(const Scene& sc) { return sc.name.rfind("exp_", 0) == 0; }

std::vector<Fidelity> fidelities(bool quick) {
  return quick ? std::vector<Fidelity>{Fidelity::Rim20, Fidelity::Circle}
               : std::vector<Fidelity>{Fidelity::Rim20, Fidelity::Rim40, Fidelity::Rim80, Fidelity::Rim160,
                                       Fidelity::Circle};
}

std::vector<Task> sweepTasks(const std::vector<Scene>& scenes, bool quick) {
  const std::vector<Fidelity> fids = fidelities(quick);
  std::vector<Task> tasks;
  for (const Scene& sc : scenes) {
    const bool experiment = isExperiment(sc);
    for (Setting s : settingsGrid(quick)) {
      if (!sc.uses_fidelity) { tasks.push_back({&sc, s}); continue; }
      for (Fidelity f : fids) {
        // the experiments against a reference: the report's wheel and the
        // continuous one (the reference run per fidelity is the cost)
        if (experiment && f != Fidelity::Rim20 && f != Fidelity::Circle) continue;
        // implicit Euler costs n + 1 evaluations per step: skip the
        // finest rims, whose evaluations are 8x dearer
        if (s.integrator == IntegratorKind::ImplicitEuler && (f == Fidelity::Rim80 || f == Fidelity::Rim160)) continue;
        s.fidelity = f;
        tasks.push_back({&sc, s});
      }
    }
  }
  return tasks;
}

// reference runs of the experiments: RK4 at a step far below every
// stability and accuracy scale of the model
std::vector<Task> referenceTasks(const std::vector<Scene>& scenes, bool quick) {
  std::vector<Task> refs;
  for (const Scene& sc : scenes)
    if (isExperiment(sc))
      for (Fidelity f : {Fidelity::Rim20, Fidelity::Circle})
        refs.push_back({&sc, Setting{IntegratorKind::Rk4, quick ? 1e-4 : 2e-5, 1e-6, f}});
  return refs;
}

std::vector<Result> runTasks(const std::vector<Task>& tasks, int jobs) {
  std::vector<Result> results(tasks.size());
  std::mutex print;
  std::atomic<int> done{0};
  std::fprintf(stderr, "sweep: %zu cells on %d threads\n", tasks.size(), jobs);
  parallelFor(tasks.size(), jobs, [&](size_t i) {
    results[i] = tasks[i].scene->run(tasks[i].setting);
    const int d = ++done;
    if (d % 25 == 0) {
      std::lock_guard<std::mutex> lock(print);
      std::fprintf(stderr, "  %d/%zu\n", d, tasks.size());
    }
  });
  return results;
}

// experiments: error against the reference of the same fidelity (the last
// `refs` results, dropped afterwards)
void scoreExperiments(std::vector<Result>& results, size_t refs) {
  const size_t cells = results.size() - refs;
  std::map<std::string, double> reference;
  for (size_t i = cells; i < results.size(); ++i)
    reference[results[i].scene + fidelityName(results[i].setting.fidelity)] = results[i].value;
  for (size_t i = 0; i < cells; ++i) {
    Result& r = results[i];
    auto it = reference.find(r.scene + fidelityName(r.setting.fidelity));
    if (it == reference.end() || !r.healthy) continue;
    r.expected = it->second;
    r.error = std::abs(r.value - r.expected) / std::abs(r.expected);
  }
  results.resize(cells);
}

void sweep(Report& rep, bool quick, int jobs) {
  std::vector<Task> tasks = sweepTasks(rep.scenes, quick);
  const std::vector<Task> refs = referenceTasks(rep.scenes, quick);
  tasks.insert(tasks.end(), refs.begin(), refs.end());
  std::vector<Result> results = runTasks(tasks, jobs);
  scoreExperiments(results, refs.size());
  rep.cells = std::move(results);
}

// --- 3. an hour of simulated time -------------------------------------------

// the cheapest setting that stays within 2% on the plain scene with the
// continuous wheel
const Result* cheapestWithin2Percent(const std::vector<Result>& cells) {
  const Result* cheapest = nullptr;
  for (const Result& r : cells)
    if (r.scene == "plain_s1" && r.healthy && r.error < 0.02 && r.setting.fidelity == Fidelity::Circle &&
        (!cheapest || r.evalsPerSim() < cheapest->evalsPerSim()))
      cheapest = &r;
  return cheapest;
}

void runHours(Report& rep, bool quick, int jobs) {
  const Result* cheapest = cheapestWithin2Percent(rep.cells);
  if (!cheapest || quick) return;
  std::fprintf(stderr, "an hour at %s\n", cheapest->setting.label().c_str());
  std::vector<HourRun> hours(2);
  parallelFor(2, jobs, [&](size_t i) { hours[i] = hour(i == 0 ? "plain_s1" : "parked_20", cheapest->setting); });
  rep.hours = hours;
}

void writeOutputs(const Report& rep, const Args& a) {
  writeCsv(rep, a.out + "/tradeoff.csv");
  writeStabilityCsv(rep, a.out + "/stability.csv");
  writeRoadCsv(rep, a.out + "/road.csv");
  writePlots(rep, a.out, a.img);
  writeMarkdown(rep, a.docs);
  std::fprintf(stderr, "done in %.0f s: %s, %s/work_precision.png, %s/stability_map.png, %s/tradeoff.csv\n",
               rep.total_wall_seconds, a.docs.c_str(), a.img.c_str(), a.img.c_str(), a.out.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"groundsim accuracy/cost trade-off and stability map"};
  Args a;
  addOptions(app, a);
  CLI11_PARSE(app, argc, argv);
  std::filesystem::create_directories(a.out);
  std::filesystem::create_directories(a.img);
  const auto start = std::chrono::steady_clock::now();

  Report rep;
  rep.jobs = a.jobs;
  rep.out_dir = a.out;
  rep.command = "scripts/accuracy.sh" + std::string(a.quick ? " --quick" : "");
  // 0. the sedan's manoeuvres against their converged references
  sweepRoad(rep, a);
  if (a.road_only) {
    printRoad(rep, a.out);
    return 0;
  }
  rep.scenes = analyticScenes();
  for (auto& s : reportExperiments()) rep.scenes.push_back(s);
  // 1. the sweep: every scene x setting (x fidelity for car scenes)
  sweep(rep, a.quick, a.jobs);
  // 2. the stability map
  std::fprintf(stderr, "stability map\n");
  rep.stability = stabilityMap(a.quick);
  // 3. an hour of simulated time at the cheapest setting within 2%
  runHours(rep, a.quick, a.jobs);
  rep.total_wall_seconds = secondsSince(start);
  writeOutputs(rep, a);
  return 0;
}
