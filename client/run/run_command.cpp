// `groundsim run SCENARIO.json`: loads and validates a scenario, simulates
// it in this process with groundsim::Simulator, writes frames at the output
// rate to CSV, optionally plots speed per frame, and prints a summary.
//
// Exit codes (also in `run --help` and docs/reliability.md): 0 done, 1
// output file problem, 2 invalid scenario or arguments (including a model
// over the budget), 3 the simulation diverged (the summary gives the
// reason), 4 out of memory or an internal error (the message says which).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <limits>
#include <new>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "../commands.hpp"
#include "physics/integrators/integrator.hpp"
#include "physics/simulator.hpp"
#include "physics/checks/telemetry.hpp"
#include "accuracy/live_estimate.hpp"
#include "accuracy/refinement.hpp"
#include "accuracy/pilot.hpp"
#include "scenario/presets.hpp"
#include "scenario/scenario.hpp"
#include "speed_plot.hpp"
#include "telemetry_csv.hpp"

namespace groundsim::cli {
namespace {

using Clock = std::chrono::steady_clock;

constexpr int kExitOutput = 1, kExitInvalid = 2, kExitDiverged = 3, kExitInternal = 4;

constexpr const char* kExitCodes =
    "Exit codes: 0 done; 1 an output file (CSV, plot) could not be written; 2 invalid scenario, file or\n"
    "arguments, or a model over the budget (--max-*); 3 the simulation diverged; 4 out of memory or\n"
    "an internal error.\n";

struct RunOptions {
  std::string scenario_path;
  std::optional<double> duration;
  std::vector<std::string> overrides;
  std::string preset, integrator;
  std::optional<double> dt;
  std::string tolerance;  // "0.01" or "1%": the accuracy section's tolerance
  bool pilot_report = false;
  std::string csv_path;
  std::string hits_path;
  std::string plot_path;
  bool quiet = false;
  scenario::Budget budget;  // raised by the --max-* flags
};

// A step count from a double, saturating instead of overflowing: the
// validated ranges keep every count far below 2^62, this keeps the
// conversion defined whatever the inputs.
long long toCount(double x) {
  constexpr double kMax = 4.6e18;  // < 2^62
  if (!(x > 0.0)) return 0;
  if (!(x < kMax)) return static_cast<long long>(kMax);
  return std::llround(x);
}

double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// A single updating line on a terminal; on a pipe or log file, a plain line
// every few seconds instead of carriage-return clutter. Silent for the
// first ~2 s of wall time: short runs need no progress report.
class Progress {
 public:
  Progress(bool enabled, double duration) : enabled_(enabled), duration_(duration), tty_(isatty(STDERR_FILENO)) {}

  void update(double sim_t) {
    if (!enabled_) return;
    const double wall = secondsSince(start_);
    if (wall < 2.0 || wall - last_ < (tty_ ? 0.2 : 5.0)) return;
    last_ = wall;
    const double rate = sim_t / wall;
    const double eta = rate > 0 ? (duration_ - sim_t) / rate : 0.0;
    std::fprintf(stderr, "%st = %.2f / %.2f s (%3.0f%%), %.2f sim-s per wall-s, %.0f s left%s", tty_ ? "\r" : "",
                 sim_t, duration_, 100.0 * sim_t / duration_, rate, eta, tty_ ? "\033[K" : "\n");
    shown_ = true;
  }
  void done() {
    if (shown_ && tty_) std::fprintf(stderr, "\r\033[K");
  }

 private:
  bool enabled_;
  double duration_;
  bool tty_;
  Clock::time_point start_ = Clock::now();
  double last_ = 0.0;
  bool shown_ = false;
};

void printIssues(const std::string& file, const scenario::ScenarioError& e) {
  const std::string name = scenario::quote(file);
  for (const scenario::Issue& i : e.issues()) {
    // file-level problems (missing, empty, malformed) already name the file
    if (i.path.empty() && i.message.rfind(name, 0) == 0)
      std::cerr << "error: " << i.message << "\n";
    else
      std::cerr << "error: " << name << ": " << i.str() << "\n";
  }
  if (e.omitted() > 0)
    std::cerr << "error: " << name << ": and " << e.omitted() << " more problem" << (e.omitted() == 1 ? "" : "s")
              << "\n";
}

// Frames at t = k / rate, each at the step nearest to it.
long long frameTick(long long k, double rate, double dt) { return toCount(static_cast<double>(k) / (rate * dt)); }

struct RunResult {
  long long steps = 0;
  double wall = 0.0;
  double energy_start = 0.0, energy_end = 0.0;
  std::vector<VehicleSample> final_samples;
  std::vector<Hit> hits;  // contact between bodies: ended ones, then those still under way
  std::size_t hits_dropped = 0;
  struct Refinement {
    double t;
    int substeps;
  };
  std::vector<Refinement> refinements;  // at a safe point, when the live estimate asked
};

// The frame loop: step to each frame's tick, sample every vehicle, write.
// live: the live error estimate, stepped around every step (then one step
// at a time); refinement: what is done when it passes the tolerance (a
// finer step at a safe point between chunks of steps, or one warning).
RunResult simulate(Simulator& sim, const scenario::Scene& scene, std::ostream* csv, bool progress,
                   accuracy::LiveEstimate* live = nullptr, accuracy::RefinementPolicy refinement = {}) {
  const double dt = sim.model().opt.dt;
  const long long last_frame = toCount(std::floor(scene.duration * scene.output_rate + 1e-9));
  const long long end_tick = toCount(scene.duration / dt);
  RunResult r;
  r.energy_start = sim.state().initial_energy;
  Progress bar(progress, scene.duration);
  const auto t0 = Clock::now();
  // the simulator keeps at most ContactLog::kMaxEnded ended hits: with
  // contact between bodies, collect them every few steps
  const long long most = sim.model().collisions ? 64 : 2048;
  auto collectHits = [&]() {
    if (!sim.model().collisions) return;
    for (Hit& h : sim.takeEndedHits()) r.hits.push_back(h);
  };

  accuracy::Refiner refiner(refinement);
  // n steps, with the live estimate around each when there is one; a
  // refinement at the end of a chunk (a frame, or a chunk's last step)
  auto advance = [&](long long n) {
    if (!accuracy::stepWatched(scene, sim, n, live)) return false;
    if (!live) return true;
    const accuracy::Refiner::Decision d = refiner.watch(sim, *live, accuracy::safeToRefine(sim));
    if (d.substeps > 0) r.refinements.push_back({sim.state().t, d.substeps});
    if (!d.message.empty())
      std::fprintf(stderr, "%s%s%s\n", progress ? "\n" : "", d.warning ? "warning: " : "", d.message.c_str());
    return true;
  };
  auto writeFrame = [&]() {
    r.final_samples.clear();
    const double estimate = live ? live->estimate() : std::numeric_limits<double>::quiet_NaN();
    for (size_t v = 0; v < scene.cars.size(); ++v) {
      // energy is the whole scene's: compute it once per frame
      VehicleSample s = sampleVehicle(sim, scene.cars[v].vehicle, v == 0);
      if (v > 0) s.energy = r.final_samples.front().energy;
      if (csv) *csv << csvRow(s, scene.vehicle_names[v], estimate) << '\n';
      r.final_samples.push_back(s);
    }
  };

  // without a CSV nobody reads the frames: step straight to the end and
  // sample once there (a frame's sample costs as much as a few steps). With
  // the live estimate the frames stay: they are where a refinement may
  // come, and the run must not depend on whether a CSV is written.
  if (csv) writeFrame();
  const long long frames = csv || live ? last_frame : 0;
  for (long long k = 1; k <= frames && sim.healthy(); ++k) {
    const long long target = std::min(frameTick(k, scene.output_rate, dt), end_tick);
    while (sim.state().tick < target) {
      // progress is checked between chunks: a clock read per step costs more than the step
      const long long chunk = std::min<long long>(target - sim.state().tick, most);
      const bool ok = advance(chunk);  // with the road cars' control tables
      collectHits();
      if (!ok) break;
      bar.update(sim.state().t);
    }
    if (csv) writeFrame();  // after a divergence: the last finite state, health set
  }
  // a duration that is not a whole number of frames still runs to its end
  while (sim.healthy() && sim.state().tick < end_tick) {
    const bool ok = advance(std::min<long long>(end_tick - sim.state().tick, most));
    collectHits();
    if (!ok) break;
    bar.update(sim.state().t);
  }
  collectHits();
  if (live) live->beforeStep(sim);  // the estimate at the end
  r.hits.insert(r.hits.end(), sim.hits().begin(), sim.hits().end());
  r.wall = secondsSince(t0);
  bar.done();
  r.steps = sim.state().tick;
  r.energy_end = sim.energy().total();
  if (r.final_samples.empty() || r.final_samples.front().t != sim.state().t) {
    r.final_samples.clear();
    for (size_t v = 0; v < scene.cars.size(); ++v) r.final_samples.push_back(sampleVehicle(sim, scene.cars[v].vehicle, false));
  }
  return r;
}

// One row per hit between bodies (contact_log.hpp), in the order they ended.
bool writeHits(const std::string& path, const Model& m, const std::vector<Hit>& hits) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  if (!f) return false;
  f << "a,b,begin,end,x,y,z,closing_speed,impulse,peak_force,depth,hard\n";
  char buf[512];
  for (const Hit& h : hits) {
    std::snprintf(buf, sizeof buf, "%s,%s,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%d\n", m.groups[h.a].name.c_str(),
                  m.groups[h.b].name.c_str(), h.begin, h.end, h.where.x(), h.where.y(), h.where.z(), h.closing_speed,
                  h.impulse, h.peak_force, h.depth, h.hard ? 1 : 0);
    f << buf;
  }
  f.close();
  return static_cast<bool>(f);
}

void printSummary(const scenario::Scenario& s, const Simulator& sim, const scenario::Scene& scene,
                  const RunResult& r) {
  const Model& m = sim.model();
  std::printf("scenario   %s%s%s\n", s.name.c_str(), s.description.empty() ? "" : ": ", s.description.c_str());
  std::printf("simulated  %.4g s of %.4g s in %lld steps (dt %.3g s, %s, ground: %s)\n", sim.state().t, s.duration,
              r.steps, m.opt.dt, integratorName(m.opt.integrator), m.ground->describe().c_str());
  const double wall = std::max(r.wall, 1e-9);
  std::printf("wall time  %.3f s: %.0f steps/s, %.3g sim-s per wall-s\n", r.wall, r.steps / wall,
              sim.state().t / wall);
  for (size_t v = 0; v < r.final_samples.size(); ++v) {
    const VehicleSample& f = r.final_samples[v];
    std::printf("vehicle    %-10s position (%.4f, %.4f, %.4f) m, speed %.4f m/s, velocity (%.4f, %.4f, %.4f) m/s\n",
                scene.vehicle_names[v].c_str(), f.position.x(), f.position.y(), f.position.z(), f.speed,
                f.velocity.x(), f.velocity.y(), f.velocity.z());
  }
  if (m.collisions) {
    int hard = 0;
    for (const Hit& h : r.hits) hard += h.hard;
    std::printf("hits       %zu between bodies (%d hard)%s\n", r.hits.size(), hard,
                r.hits_dropped ? " and more not kept" : "");
  }
  for (const SceneObject& o : m.objects) {
    if (o.body < 0) continue;
    const Vec3 x0 = bodyPos(scene.built.initial.y, o.body), x = bodyPos(sim.state().y, o.body);
    const Quat q = Quat(bodyRot(sim.state().y, o.body)).normalized();
    const double tilt = std::acos(std::clamp((q * Vec3::UnitZ()).z(), -1.0, 1.0)) * 180.0 / 3.14159265358979323846;
    std::printf("object     %-10s position (%.4f, %.4f, %.4f) m, moved %.3f m, tilted %.1f deg\n", o.name.c_str(),
                x.x(), x.y(), x.z(), (x - x0).norm(), tilt);
  }
  std::printf("energy     start %.6g J, end %.6g J (drive work %.4g J)\n", r.energy_start, r.energy_end,
              sim.state().drive_work);
  if (sim.healthy())
    std::printf("health     ok\n");
  else
    std::printf("health     DIVERGED (%s) at t = %.6g s: %s\n", healthName(sim.state().health), sim.state().t,
                sim.state().health_reason.c_str());
}

// "0.01" or "1%" as a fraction; nullopt for anything else (CLI validator).
std::optional<double> parseTolerance(const std::string& text) {
  std::string t = text;
  double scale = 1.0;
  if (!t.empty() && t.back() == '%') {
    t.pop_back();
    scale = 0.01;
  }
  try {
    size_t used = 0;
    const double v = std::stod(t, &used);
    if (used != t.size() || !std::isfinite(v)) return std::nullopt;
    return v * scale;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

// Load, override, validate: the problems of the file are thrown at once
// (ScenarioError). Precedence: file < --preset < --integrator/--dt < --set.
scenario::Scenario loadScenario(const RunOptions& o) {
  const scenario::Budget& budget = o.budget;
  nlohmann::json doc = scenario::loadScenarioDocument(o.scenario_path, budget);
  if (doc.is_object() && !doc.contains("name")) doc["name"] = std::filesystem::path(o.scenario_path).stem().string();
  if (!o.preset.empty() && doc.is_object()) {
    doc["preset"] = o.preset;
    scenario::applyPreset(doc, /*force=*/true);
  }
  if (!o.integrator.empty()) scenario::applyOverride(doc, "physics.integrator=\"" + o.integrator + "\"", budget);
  if (o.dt) scenario::applyOverride(doc, "physics.dt=" + nlohmann::json(*o.dt).dump(), budget);
  // --tolerance sets the accuracy section; its range is validated there
  if (!o.tolerance.empty())
    scenario::applyOverride(doc, "accuracy.tolerance=" + nlohmann::json(*parseTolerance(o.tolerance)).dump(), budget);
  for (const std::string& a : o.overrides) scenario::applyOverride(doc, a, budget);
  if (o.duration) scenario::applyOverride(doc, "duration=" + nlohmann::json(*o.duration).dump(), budget);
  return scenario::parseScenario(std::move(doc), budget,
                                 scenario::FileAccess::local(std::filesystem::path(o.scenario_path).parent_path().string()));
}

// a tolerance: the pilot chooses integrator, step and contact substeps, and
// s becomes the chosen scenario
std::optional<accuracy::Choice> chooseIfAsked(scenario::Scenario& s, const RunOptions& o) {
  if (!s.accuracy) return std::nullopt;
  accuracy::Choice choice = accuracy::chooseSettings(s, s.accuracy->tolerance, accuracy::pilotOptions(*s.accuracy, o.budget));
  if (!o.quiet) {
    std::fprintf(stderr, "accuracy: %s\n", choice.line().c_str());
    if (o.pilot_report) std::fprintf(stderr, "%s", choice.report().c_str());
  }
  if (!choice.meets)
    std::fprintf(stderr, "warning: no setting is predicted to meet the tolerance %g; running the closest\n",
                 s.accuracy->tolerance);
  s = choice.scenario;
  return choice;
}

// The CSV: the requested file, or a temporary one for the plot alone.
struct CsvOutput {
  std::string path;
  bool temporary = false;
  std::ofstream out;
};

// false after saying why not
bool openCsv(const RunOptions& o, CsvOutput& c) {
  c.path = o.csv_path;
  if (c.path.empty() && !o.plot_path.empty()) {
    const char* tmpdir = std::getenv("TMPDIR");
    c.path = std::string(tmpdir && *tmpdir ? tmpdir : "/tmp") + "/groundsim-run-XXXXXX";
    const int fd = mkstemp(c.path.data());
    if (fd < 0) {
      std::cerr << "error: cannot create a temporary CSV for the plot\n";
      return false;
    }
    close(fd);
    c.temporary = true;
  }
  if (c.path.empty()) return true;
  c.out.open(c.path, std::ios::binary | std::ios::trunc);
  if (!c.out) {
    std::cerr << "error: cannot write " << scenario::quote(c.path) << "\n";
    return false;
  }
  c.out << csvHeader() << '\n';
  return true;
}

// the live error estimate of a run with an accuracy section, told what the
// pilot predicted
std::unique_ptr<accuracy::LiveEstimate> liveEstimate(const scenario::Scenario& s,
                                                     const std::optional<accuracy::Choice>& choice) {
  if (!s.accuracy || !s.accuracy->live_estimate) return nullptr;
  accuracy::LiveEstimateOptions lo;
  lo.duration = s.duration;
  auto live = std::make_unique<accuracy::LiveEstimate>(s, accuracy::nominalOrder(s.options.integrator), lo);
  if (choice) live->expect(choice->prediction(), s.duration);
  return live;
}

// the choice, the pilot's share of what the user waited for (pilot and run
// together), the live estimate and the refinements
void printAccuracy(const accuracy::Choice& choice, const accuracy::LiveEstimate* live, const RunResult& r) {
  std::printf("accuracy   tolerance %.3g: %s\n", choice.tolerance, choice.line().c_str());
  const double total = std::max(choice.pilot_wall_seconds + r.wall, 1e-9);
  std::printf("pilot      %.3g s of the scene per trial, %.3g s wall: %.0f%% of pilot and run (%.3gx the run)\n",
              choice.pilot_duration, choice.pilot_wall_seconds, 100.0 * choice.pilot_wall_seconds / total,
              choice.pilot_wall_seconds / std::max(r.wall, 1e-9));
  std::printf("pilot work %.3g work units, %.0f%% of the run's predicted %.3g%s%s\n", choice.pilot_work,
              100.0 * choice.pilot_work / std::max(choice.run_work, 1e-9), choice.run_work,
              choice.pilot_bound.empty() ? "" : ": ", choice.pilot_bound.c_str());
  if (live)
    std::printf("estimate   %.3g (path %.3g, speed %.3g; %d windows, shadow steps %.1f%% of the run's)%s\n",
                live->estimate(), live->pathEstimate(), live->speedEstimate(), live->windowsMeasured(),
                100.0 * static_cast<double>(live->shadowSteps()) / std::max(1.0, static_cast<double>(r.steps)),
                live->estimate() > choice.tolerance ? "  ABOVE THE TOLERANCE" : "");
  for (const RunResult::Refinement& f : r.refinements)
    std::printf("refined    to %d integrator substeps per step at t = %.4g s\n", f.substeps, f.t);
}

// The outputs after the run: the CSV closed, the hits written, the summary,
// the plot. kExitOutput when one of them failed, else 0.
int writeOutputs(const RunOptions& o, const scenario::Scenario& s, const scenario::Scene& scene, const Simulator& sim,
                 const RunResult& r, CsvOutput& csv, const std::optional<accuracy::Choice>& choice,
                 const accuracy::LiveEstimate* live) {
  int code = 0;
  if (csv.out.is_open()) {
    csv.out.close();
    if (!csv.out) {
      std::cerr << "error: writing " << scenario::quote(csv.path) << " failed\n";
      code = kExitOutput;
    }
  }
  if (!o.hits_path.empty() && !writeHits(o.hits_path, sim.model(), r.hits)) {
    std::cerr << "error: cannot write " << scenario::quote(o.hits_path) << "\n";
    code = kExitOutput;
  }
  if (!o.quiet) printSummary(s, sim, scene, r);
  if (!o.quiet && choice) printAccuracy(*choice, live, r);
  if (!o.plot_path.empty() && code == 0) {
    const std::string err = drawSpeedPlot({csv.path, o.plot_path, scene.vehicle_names, s.output_rate,
                                           s.name + ": speed of the body per frame"});
    if (!err.empty()) {
      std::cerr << "error: plot " << scenario::quote(o.plot_path) << ": " << err << "\n";
      code = kExitOutput;
    }
  }
  if (csv.temporary) std::remove(csv.path.c_str());
  return code;
}

int run(const RunOptions& o) {
  scenario::Scenario s;
  std::optional<accuracy::Choice> choice;
  std::optional<scenario::Scene> scene;
  try {
    s = loadScenario(o);
    choice = chooseIfAsked(s, o);
    scene = scenario::buildScene(s);
  } catch (const scenario::ScenarioError& e) {
    printIssues(o.scenario_path, e);
    return kExitInvalid;
  }
  for (const std::string& w : scene->warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  CsvOutput csv;
  if (!openCsv(o, csv)) return kExitOutput;
  Simulator sim(scene->built.model, scene->built.initial);
  const std::unique_ptr<accuracy::LiveEstimate> live = liveEstimate(s, choice);
  const accuracy::RefinementPolicy refinement =
      s.accuracy ? accuracy::refinementPolicy(*s.accuracy) : accuracy::RefinementPolicy{};
  const RunResult r = simulate(sim, *scene, csv.out.is_open() ? &csv.out : nullptr, !o.quiet, live.get(), refinement);
  const int code = writeOutputs(o, s, *scene, sim, r, csv, choice, live.get());
  if (!sim.healthy()) {
    std::cerr << "error: the simulation diverged at t = " << sim.state().t << " s ("
              << healthName(sim.state().health) << "): " << sim.state().health_reason << "\n";
    return kExitDiverged;
  }
  return code;
}

// No exception leaves the runner as an abort: out of memory and anything
// unexpected become a message and exit 4.
int guardedRun(const RunOptions& o) {
  try {
    return run(o);
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "error: out of memory (lower the model's size, or the --max-* limits)\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: internal error: %s\n", scenario::quote(e.what(), 1000).c_str());
  }
  return kExitInternal;
}

void addBudgetOptions(CLI::App* cmd, scenario::Budget& b) {
  const std::string g = "Model budget (docs/reliability.md)";
  auto add = [&](const char* name, auto& field, const char* what) {
    cmd->add_option(std::string("--") + name, field, what)->capture_default_str()->group(g);
  };
  add("max-document-bytes", b.max_document_bytes, "largest scenario file, bytes");
  cmd->add_option("--max-depth", b.max_depth, "deepest nesting of JSON objects and arrays")
      ->capture_default_str()->group(g)->check(CLI::Range(1, 1000));
  add("max-json-values", b.max_json_values, "most JSON values in the document");
  add("max-expression-length", b.max_expression_length, "longest ground expression, characters");
  cmd->add_option("--max-vehicles", b.max_vehicles, "most vehicles")->capture_default_str()->group(g)
      ->check(CLI::PositiveNumber);
  add("max-points", b.max_points, "most mass/attachment points in the model");
  add("max-springs", b.max_springs, "most springs");
  add("max-particles", b.max_particles, "most free point masses");
  add("max-state", b.max_state, "largest state vector (13 per body, 6 per particle)");
  add("max-implicit-state", b.max_implicit_state, "largest state for implicit_euler (dense matrices)");
  cmd->add_option("--max-steps", b.max_steps, "most integrator steps (duration / dt x substeps)")
      ->capture_default_str()->group(g)->check(CLI::PositiveNumber);
  cmd->add_option("--max-work", b.max_work, "most work units (steps x cost of a step)")
      ->capture_default_str()->group(g)->check(CLI::PositiveNumber);
}

}  // namespace

void registerRunCommand(CLI::App& app) {
  auto opts = std::make_shared<RunOptions>();
  CLI::App* cmd = app.add_subcommand("run", "Simulate a scenario file in this process (no server)");
  cmd->add_option("scenario", opts->scenario_path, "Scenario JSON file (docs/scenario.md)")->required();
  cmd->add_option("--duration", opts->duration, "Simulated time in s (overrides the file's duration)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--preset", opts->preset, "Speed/accuracy preset, replacing the file's settings it names")
      ->check(CLI::IsMember({"fast", "balanced", "accurate"}));
  cmd->add_option("--integrator", opts->integrator, "Integrator (overrides the file and the preset)")
      ->check(CLI::IsMember({"semi_implicit_euler", "velocity_verlet", "rk4", "implicit_euler", "adaptive"}));
  cmd->add_option("--dt", opts->dt, "Step in s (overrides the file and the preset)")->check(CLI::PositiveNumber);
  cmd->add_option("--tolerance", opts->tolerance,
                  "The error you accept (0.01 or 1%): a pilot on the scene chooses integrator, step and contact "
                  "substeps, and a live estimate watches the run (docs/accuracy.md, \"Accuracy on demand\")")
      ->check(CLI::Validator(
          [](std::string& v) -> std::string {
            return parseTolerance(v) ? std::string() : "--tolerance: a number (0.01) or a percentage (1%), got " + v;
          },
          "TOLERANCE"))
      ->excludes("--preset")
      ->excludes("--integrator")
      ->excludes("--dt");
  cmd->add_flag("--pilot-report", opts->pilot_report, "With a tolerance: print what the pilot learnt of each integrator");
  cmd->add_option("--set", opts->overrides, "Override a value before validation: key.path=value (repeatable)")
      ->allow_extra_args(false);
  cmd->add_option("--csv", opts->csv_path, "Write frames at the output rate to this CSV file");
  cmd->add_option("--hits", opts->hits_path,
                  "Write the hits between bodies (which pair, when, where, closing speed, impulse, peak force) to this CSV file");
  cmd->add_option("--plot", opts->plot_path, "Plot speed per frame to this PNG (needs gnuplot)");
  cmd->add_flag("-q,--quiet", opts->quiet, "No progress line and no summary");
  addBudgetOptions(cmd, opts->budget);
  cmd->footer(kExitCodes);
  cmd->callback([opts]() {
    const int code = guardedRun(*opts);
    if (code != 0) throw CLI::RuntimeError(code);
  });
}

}  // namespace groundsim::cli
