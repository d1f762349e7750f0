// `tolerance_sweep`: for each scene of tolerance_scenes.cpp, the converged
// reference, the oracle (every integrator at every ladder step over the
// whole duration: the cheapest setting that truly meets each tolerance),
// the setting chooseSettings picks from its pilot, that setting's realised
// error and cost against the oracle's, and the live estimate against the
// realised error. Prints a table per tolerance (docs/accuracy.md, "Accuracy
// on demand") and writes every cell to --csv.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "accuracy/error_measure.hpp"
#include "accuracy/live_estimate.hpp"
#include "accuracy/model_options.hpp"
#include "accuracy/pilot.hpp"
#include "accuracy/trajectory.hpp"
#include "physics/checks/stability.hpp"
#include "physics/forces/body_contact.hpp"
#include "physics/integrators/integrator.hpp"
#include "scenario/scenario.hpp"
#include "tolerance_scenes.hpp"

namespace groundsim::bench {
namespace {

using accuracy::Trajectory;

struct Cell {
  IntegratorKind kind{};
  double dt = 0.0;
  double error = 0.0;
  double cost = 0.0;  // wall s per sim s
  double evals = 0.0; // force evaluations per sim s
  bool healthy = true;
  int floor = 1;      // collisions.min_substeps
};

struct Row {
  std::string scene;
  double tolerance = 0.0;
  accuracy::Choice choice;
  Cell chosen, oracle;
  bool oracle_found = false;
  double estimate = 0.0, estimate_cost = 0.0;  // live estimate at the end; shadow steps / main steps
  double live_wall_ratio = 0.0;                // wall with the estimate / without
  double windows = 0.0;                        // the windows' own estimate (without the pilot's floor)
};

std::string fmt(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.2e", x);
  return b;
}

bool accepts(const scenario::Scenario& s, IntegratorKind k) {
  try {
    scenario::buildScene(accuracy::withSettings(s, k, 1e-3));
    return true;
  } catch (const scenario::ScenarioError&) {
    return false;
  }
}

double stableDt(const scenario::Scenario& s, IntegratorKind k) {
  const scenario::Scene scene = scenario::buildScene(accuracy::withSettings(s, k, 1e-3));
  double dt = std::numeric_limits<double>::infinity();
  for (const StiffMode& m : stiffestModes(*scene.built.model)) dt = std::min(dt, m.dt_limit);
  return dt;
}

Cell runCell(const scenario::Scenario& s, IntegratorKind k, double dt, int floor, const Trajectory& ref) {
  const Trajectory t = accuracy::runTrajectory(accuracy::withSettings(s, k, dt, floor), s.duration);
  Cell c{k, dt, accuracy::compareRuns(t, ref).value(), t.cost(),
         static_cast<double>(t.evaluations) / std::max(t.duration, 1e-9), t.healthy, floor};
  return c;
}

// contact's substeps at dt: the floor of the family whose coarsest step is dt
int contactFloor(const scenario::Scenario& s, IntegratorKind k, double dt) {
  return contactSubstepsBound(*scenario::buildScene(accuracy::withSettings(s, k, dt)).built.model, dt);
}

// The chosen setting run again with the live estimate: its final value, the
// shadow's share of the steps, and the wall time against a plain run.
void liveEstimate(const accuracy::Choice& c, Row& row) {
  const scenario::Scenario& s = c.scenario;
  const scenario::Scene scene = scenario::buildScene(s);
  Simulator sim(scene.built.model, scene.built.initial);
  accuracy::LiveEstimateOptions o;
  o.duration = s.duration;
  accuracy::LiveEstimate live(s, c.order, o);
  live.expect(c.prediction(), s.duration);
  const long long n = std::llround(s.duration / s.options.dt);
  const auto t0 = std::chrono::steady_clock::now();
  for (long long i = 0; i < n; ++i) {
    live.beforeStep(sim);
    if (!scenario::stepScene(scene, sim, 1)) break;
    live.afterStep(sim);
  }
  live.beforeStep(sim);  // a last update at the end
  const double with = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  row.estimate = live.estimate();
  row.windows = std::max(live.pathEstimate(), live.speedEstimate());
  row.estimate_cost = static_cast<double>(live.shadowSteps()) / static_cast<double>(std::max<long long>(1, sim.state().tick));
  Simulator plain(scene.built.model, scene.built.initial);
  const auto t1 = std::chrono::steady_clock::now();
  scenario::stepScene(scene, plain, n);
  const double without = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  row.live_wall_ratio = with / std::max(without, 1e-9);
}

// " | model NAME gap G" when the choice swapped the model (NAME with '_'
// for spaces, for tolerance_tables.py), else the models kept out, briefly
std::string modelNote(const accuracy::Choice& c) {
  std::string out;
  for (size_t k = 0; k < c.models.size(); ++k) {
    std::string name = c.models[k].name;
    std::replace(name.begin(), name.end(), ' ', '_');
    if (static_cast<int>(k) + 1 == c.model)
      out += " | model " + name + " gap " + fmt(c.model_gap);
    else
      out += " | kept " + name + (std::isfinite(c.models[k].gap) ? " gap " + fmt(c.models[k].gap) : " (not piloted)");
  }
  return out;
}

// --- the command line -------------------------------------------------------

struct SweepOptions {
  std::vector<std::string> only;
  std::vector<double> tolerances = {0.1, 0.01, 0.001};
  std::string csv_path, configs = GROUNDSIM_CONFIGS;
  std::string reuse;
  double duration = 0.0;  // > 0: every scene runs this long (its scripted controls hold their last value)
  bool verbose = false;
};

void addOptions(CLI::App& app, SweepOptions& o) {
  app.add_option("--scenes", o.only, "Scene names (default: all)")->delimiter(',');
  app.add_option("--tolerances", o.tolerances, "Tolerances")->delimiter(',');
  app.add_option("--csv", o.csv_path, "Write every oracle cell and choice here");
  app.add_option("--configs", o.configs, "The configs directory");
  app.add_option("--reuse", o.reuse,
                 "Take the oracle cells from this --csv of an earlier sweep and the references' uncertainties from its "
                 "stdout (FILE.txt beside FILE.csv): the chooser and the live estimate only (for development)");
  app.add_option("--duration", o.duration, "Run every scene this many simulated s (the pilot's bound of long runs)")
      ->check(CLI::PositiveNumber);
  app.add_flag("-v,--verbose", o.verbose, "Print each pilot's trials and the oracle cells");
}

bool selected(const SweepOptions& o, const ToleranceScene& sc) {
  return o.only.empty() || std::find(o.only.begin(), o.only.end(), sc.name) != o.only.end();
}

// --- --reuse: an earlier sweep's cells and references' uncertainties ---------

struct Reused {
  std::map<std::string, std::vector<Cell>> cells;  // per scene
  std::map<std::string, double> uncertainty;       // per scene
};

std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> f;
  size_t a = 0;
  for (size_t b; (b = line.find(',', a)) != std::string::npos; a = b + 1) f.push_back(line.substr(a, b - a));
  f.push_back(line.substr(a));
  return f;
}

// a row of --csv: scene,kind,dt,floor,error,cost,evals,healthy
Cell cellOf(const std::vector<std::string>& f) {
  Cell c;
  for (IntegratorKind k : {IntegratorKind::SemiImplicitEuler, IntegratorKind::VelocityVerlet, IntegratorKind::Rk4})
    if (f[1] == integratorName(k)) c.kind = k;
  c.dt = std::stod(f[2]);
  c.floor = std::stoi(f[3]);
  c.error = std::stod(f[4]);
  c.cost = std::stod(f[5]);
  c.evals = std::stod(f[6]);
  c.healthy = f[7] == "1";
  return c;
}

// the cells of FILE.csv, the uncertainties from the scene headers of FILE.txt
Reused readReused(const std::string& path) {
  Reused r;
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    const std::vector<std::string> f = splitCsv(line);
    if (f.size() < 8) continue;
    r.cells[f[0]].push_back(cellOf(f));
  }
  std::ifstream txt(path.substr(0, path.rfind('.')) + ".txt");
  while (std::getline(txt, line)) {
    char name[128];
    double u = 0;
    if (std::sscanf(line.c_str(), "## %127[^:]: reference %*s dt %*s (uncertainty %lf)", name, &u) == 2)
      r.uncertainty[name] = u;
  }
  return r;
}

std::ofstream openCsv(const std::string& path) {
  std::ofstream csv;
  if (!path.empty()) {
    csv.open(path);
    csv << "scene,kind,dt,floor,error,cost,evals,healthy\n";
  }
  return csv;
}

// --- per scene: the reference and the oracle's cells -------------------------

// The reference: the highest order the scene accepts, 64 ladder steps below
// its coarsest stable step; its uncertainty from twice that step. Run on
// first use (with --reuse only if the choice is not among the cells).
struct Reference {
  const scenario::Scenario* s = nullptr;
  IntegratorKind kind{};
  double top = 0.0;  // the scene's coarsest ladder step, where the oracle's ladders start
  double dt = 0.0;
  int floor = 1;     // contact between bodies at the family's floor: its substep shrinks too
  std::optional<Trajectory> trajectory;

  const Trajectory& run() {
    if (!trajectory) trajectory = accuracy::runTrajectory(accuracy::withSettings(*s, kind, dt, floor), s->duration);
    return *trajectory;
  }
  // the reference at twice its step against it
  double uncertainty() {
    const Trajectory ref2 = accuracy::runTrajectory(accuracy::withSettings(*s, kind, 2 * dt, floor), s->duration);
    return accuracy::compareRuns(ref2, run()).value();
  }
};

Reference referenceOf(const scenario::Scenario& s) {
  Reference r;
  r.s = &s;
  r.kind = accepts(s, IntegratorKind::Rk4) ? IntegratorKind::Rk4 : IntegratorKind::VelocityVerlet;
  r.top = accuracy::ladderStepAtMost(std::min(0.02, 1.0 / s.output_rate));
  const double ref_top = accuracy::ladderStepAtMost(std::min(r.top, 0.9 * stableDt(s, r.kind)));
  r.dt = std::max(ref_top / 64, 2.4e-6);
  r.floor = contactFloor(s, r.kind, ref_top);
  return r;
}

bool converged(const Cell& c) { return c.healthy && c.error < 2e-5; }

// One integrator's ladder down from the top step with the automatic contact
// substeps, to the first converged cell; returns contact's need at the
// coarsest healthy step (0 if none was healthy).
int automaticLadder(const scenario::Scenario& s, IntegratorKind k, Reference& ref, std::vector<Cell>& cells) {
  int floor = 0;
  for (double h = ref.top; h >= 1e-5 * (1 - 1e-9); h /= 2) {
    cells.push_back(runCell(s, k, h, 1, ref.run()));
    if (cells.back().healthy && floor == 0) floor = contactFloor(s, k, h);
    if (converged(cells.back())) break;
  }
  return floor;
}

// The family whose floor is `floor`, as the pilot sets it.
void flooredLadder(const scenario::Scenario& s, IntegratorKind k, int floor, Reference& ref, std::vector<Cell>& cells) {
  for (double h = ref.top; h >= 1e-5 * (1 - 1e-9); h /= 2) {
    if (contactFloor(s, k, h) > floor) continue;  // unhealthy at the automatic count already
    cells.push_back(runCell(s, k, h, floor, ref.run()));
    if (converged(cells.back())) break;
  }
}

// Every integrator the scene accepts: the automatic contact substeps, then
// (in a scene with contact between bodies) the family whose floor is
// contact's need at the coarsest healthy step.
std::vector<Cell> oracleCells(const scenario::Scenario& s, Reference& ref) {
  std::vector<Cell> cells;
  for (IntegratorKind k : {IntegratorKind::SemiImplicitEuler, IntegratorKind::VelocityVerlet, IntegratorKind::Rk4}) {
    if (!accepts(s, k)) continue;
    const int floor = automaticLadder(s, k, ref, cells);
    if (floor > 1) flooredLadder(s, k, floor, ref, cells);
  }
  return cells;
}

void printCells(const std::vector<Cell>& cells) {
  for (const Cell& c : cells)
    std::printf("  cell %-19s dt %-9.3g floor %-2d error %s cost %.3g%s\n", integratorName(c.kind), c.dt, c.floor,
                fmt(c.error).c_str(), c.cost, c.healthy ? "" : " DIVERGED");
}

void writeCells(std::ofstream& csv, const std::string& scene, const std::vector<Cell>& cells) {
  for (const Cell& c : cells)
    if (csv) csv << scene << ',' << integratorName(c.kind) << ',' << c.dt << ',' << c.floor << ',' << c.error << ',' << c.cost << ','
                 << c.evals << ',' << c.healthy << '\n';
}

// --- per tolerance: the choice against the oracle ----------------------------

// The chosen setting's cell: the oracle's own if it is among them, else run
// against the reference.
Cell chosenCell(const scenario::Scenario& s, const accuracy::Choice& choice, const std::vector<Cell>& cells,
                Reference& ref) {
  const auto same = std::find_if(cells.begin(), cells.end(), [&](const Cell& c) {
    return choice.model == 0 && c.kind == choice.integrator && std::abs(c.dt / choice.dt - 1) < 1e-9 &&
           c.floor == choice.contact_substeps;
  });
  if (same != cells.end()) return *same;
  if (choice.model == 0) return runCell(s, choice.integrator, choice.dt, choice.contact_substeps, ref.run());
  // another model chosen: its run against the scene as written's
  // reference; its evaluations counted in the user's model's work
  // (the oracle's cells are the user's model's), so the cost compares
  const Trajectory t = accuracy::runTrajectory(choice.scenario, s.duration);
  return Cell{choice.integrator, choice.dt, accuracy::compareRuns(t, ref.run()).value(), t.cost(),
              static_cast<double>(t.evaluations) / std::max(t.duration, 1e-9) *
                  accuracy::workPerEvaluation(choice.scenario) / accuracy::workPerEvaluation(s),
              t.healthy, choice.contact_substeps};
}

// the oracle: the fewest force evaluations per simulated second (the
// chooser's own cost, exact), ties to the smaller wall time
void findOracle(const std::vector<Cell>& cells, Row& row) {
  for (const Cell& c : cells)
    if (c.healthy && c.error <= row.tolerance &&
        (!row.oracle_found || c.evals < row.oracle.evals ||
         (c.evals == row.oracle.evals && c.cost < row.oracle.cost))) {
      row.oracle = c;
      row.oracle_found = true;
    }
}

void printRow(const Row& row, bool verbose) {
  std::printf("tol %-6g chose %-19s dt %-9.3g pred %s real %s | oracle %-19s dt %-9.3g cost x%.2f evals x%.2f | "
              "estimate %s (x%.2f, shadow %.0f%%, wall x%.2f, windows %s) | pilot %.2f s%s\n",
              row.tolerance, integratorName(row.choice.integrator), row.choice.dt, fmt(row.choice.predicted_error).c_str(),
              fmt(row.chosen.error).c_str(), row.oracle_found ? integratorName(row.oracle.kind) : "-",
              row.oracle.dt, row.oracle_found ? row.chosen.cost / row.oracle.cost : 0.0,
              row.oracle_found ? row.chosen.evals / row.oracle.evals : 0.0,
              fmt(row.estimate).c_str(), row.estimate / std::max(row.chosen.error, 1e-300),
              100 * row.estimate_cost, row.live_wall_ratio, fmt(row.windows).c_str(),
              row.choice.pilot_wall_seconds, modelNote(row.choice).c_str());
  if (verbose) std::printf("%s", row.choice.report().c_str());
  std::fflush(stdout);
}

Row toleranceRow(const ToleranceScene& sc, const scenario::Scenario& s, double tol, const std::vector<Cell>& cells,
                 Reference& ref) {
  Row row;
  row.scene = sc.name;
  row.tolerance = tol;
  accuracy::PilotOptions po;
  row.choice = accuracy::chooseSettings(s, tol, po);
  row.chosen = chosenCell(s, row.choice, cells, ref);
  findOracle(cells, row);
  liveEstimate(row.choice, row);
  return row;
}

// One scene: its reference, the oracle's cells (or --reuse's), then a row
// per tolerance, each printed as it is done.
std::vector<Row> sweepScene(const ToleranceScene& sc, const SweepOptions& o, const Reused& reused, std::ofstream& csv) {
  ToleranceScene scene = sc;
  if (o.duration > 0.0) scene.overrides.push_back("duration=" + std::to_string(o.duration));
  const scenario::Scenario s = loadToleranceScene(o.configs, scene);
  const auto w0 = std::chrono::steady_clock::now();
  Reference ref = referenceOf(s);
  std::vector<Cell> cells;
  double uncertainty = 0.0;
  if (!o.reuse.empty()) {
    const auto it = reused.cells.find(sc.name);
    if (it != reused.cells.end()) cells = it->second;
    const auto u = reused.uncertainty.find(sc.name);
    if (u != reused.uncertainty.end()) uncertainty = u->second;
  } else {
    uncertainty = ref.uncertainty();
    cells = oracleCells(s, ref);
  }
  if (o.verbose) printCells(cells);
  if (o.reuse.empty()) writeCells(csv, sc.name, cells);
  std::printf("\n## %s: reference %s dt %.3g (uncertainty %s), %zu oracle cells, %.1f s\n", sc.name.c_str(),
              integratorName(ref.kind), ref.dt, fmt(uncertainty).c_str(), cells.size(),
              std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count());
  std::vector<Row> rows;
  for (double tol : o.tolerances) {
    rows.push_back(toleranceRow(sc, s, tol, cells, ref));
    printRow(rows.back(), o.verbose);
  }
  return rows;
}

// the verdicts of docs/accuracy.md, per tolerance
void printVerdicts(const std::vector<Row>& rows, const std::vector<double>& tolerances) {
  for (double tol : tolerances) {
    int n = 0, within = 0, over3 = 0, cheap = 0, est3 = 0;
    for (const Row& r : rows) {
      if (r.tolerance != tol) continue;
      ++n;
      within += r.chosen.error <= tol;
      over3 += r.chosen.error > 3 * tol;
      cheap += r.oracle_found && r.chosen.evals <= 2 * r.oracle.evals;
      const double q = r.estimate / std::max(r.chosen.error, 1e-300);
      est3 += (q >= 1.0 / 3 && q <= 3) || (r.chosen.error < 1e-12 && r.estimate < 1e-9);
    }
    std::printf("\ntolerance %g: %d scenes, within %d, over 3x %d, evaluations <= 2x oracle %d, estimate within 3x %d\n", tol,
                n, within, over3, cheap, est3);
  }
}

}  // namespace
}  // namespace groundsim::bench

int main(int argc, char** argv) {
  using namespace groundsim::bench;
  CLI::App app{"Tolerance sweep: the chooser's settings against the oracle, per scene and tolerance"};
  SweepOptions o;
  addOptions(app, o);
  CLI11_PARSE(app, argc, argv);
  const Reused reused = o.reuse.empty() ? Reused{} : readReused(o.reuse);
  std::ofstream csv = openCsv(o.csv_path);
  std::vector<Row> rows;
  for (const ToleranceScene& sc : toleranceScenes()) {
    if (!selected(o, sc)) continue;
    const std::vector<Row> scene_rows = sweepScene(sc, o, reused, csv);
    rows.insert(rows.end(), scene_rows.begin(), scene_rows.end());
  }
  printVerdicts(rows, o.tolerances);
  return 0;
}
