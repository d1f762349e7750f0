#include "report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace groundsim::accuracy {
namespace {

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

std::string dtText(double dt) { return std::isinf(dt) ? "any tried" : dt == 0 ? "none" : fmt("%.3g", dt); }

bool sameSetting(const Setting& a, const Setting& b) {
  return a.integrator == b.integrator && a.dt == b.dt && a.tolerance == b.tolerance;
}

// Distinct settings in sweep order.
std::vector<Setting> settingsOf(const std::vector<Result>& cells, const std::string& scene) {
  std::vector<Setting> out;
  for (const Result& r : cells)
    if (r.scene == scene && std::none_of(out.begin(), out.end(), [&](const Setting& s) { return sameSetting(s, r.setting); }))
      out.push_back(r.setting);
  return out;
}

std::string errorText(const Result& r) {
  if (!r.healthy) return "diverged (" + r.status + ")";
  return std::string(r.error_unit) == "m" ? fmt("%.1e m", r.error) : fmt("%.2e", r.error);
}

const Result* find(const std::vector<Result>& cells, const std::string& scene, const Setting& s, Fidelity f) {
  for (const Result& r : cells)
    if (r.scene == scene && sameSetting(r.setting, s) && (!r.uses_fidelity || r.setting.fidelity == f)) return &r;
  return nullptr;
}

const char* kFids[] = {"rim20", "rim40", "rim80", "rim160", "circle"};
const Fidelity kFidValues[] = {Fidelity::Rim20, Fidelity::Rim40, Fidelity::Rim80, Fidelity::Rim160, Fidelity::Circle};

}  // namespace

void writeCsv(const Report& rep, const std::string& path) {
  std::ofstream f(path);
  f << "scene,integrator,dt,tolerance,fidelity,healthy,status,value,expected,error,error_unit,"
       "sim_seconds,wall_seconds,sim_per_wall,evaluations,evals_per_sim\n";
  for (const Result& r : rep.cells) {
    f << r.scene << ',' << integratorName(r.setting.integrator) << ',' << r.setting.dt << ','
      << (r.setting.integrator == IntegratorKind::Adaptive ? r.setting.tolerance : 0.0) << ','
      << (r.uses_fidelity ? fidelityName(r.setting.fidelity) : "-") << ',' << r.healthy << ',' << r.status << ',';
    // a diverged cell has no value: the CSV never carries NaN
    if (r.healthy) f << r.value << ',' << r.expected << ',' << r.error; else f << ",,";
    f << ',' << r.error_unit << ',' << r.sim_seconds << ',' << r.wall_seconds << ',' << r.simPerWall() << ','
      << r.evaluations << ',' << r.evalsPerSim() << '\n';
  }
}

void writeStabilityCsv(const Report& rep, const std::string& path) {
  std::ofstream f(path);
  f << "family,parameter,integrator,largest_dt,theory_dt,omega,largest_omega_dt,note\n";
  for (const StabilityRow& s : rep.stability)
    f << s.family << ',' << s.parameter << ',' << integratorName(s.integrator) << ','
      << (std::isinf(s.largest_dt) ? -1.0 : s.largest_dt) << ',' << (std::isinf(s.theory_dt) ? -1.0 : s.theory_dt)
      << ',' << s.omega << ',' << (std::isinf(s.largest_dt) ? -1.0 : s.omega * s.largest_dt) << ",\"" << s.note
      << "\"\n";
}

void writePlots(const Report& rep, const std::string& dir, const std::string& img) {
  // work-precision: cost (wall s per simulated s) against error, per
  // integrator and wheel model, on the two reference scenes
  std::ostringstream gp;
  gp << "set terminal pngcairo noenhanced size 1400,600 font 'sans,10'\nset output '" << img << "/work_precision.png'\n"
     << "set multiplot layout 1,2\nset logscale xy\nset grid\nset key outside right top font ',8'\n"
     << "set xlabel 'wall seconds per simulated second (lower is faster)'\nset ylabel 'relative error'\n"
     << "set format y '%.0e'\nset format x '%.0e'\nset yrange [1e-13:2]\n"
     << "set label 1 'errors below 1e-12 (round-off) drawn at 1e-12' at graph 0.02, graph 0.03\n";
  const char* integrators[] = {"semi_implicit_euler", "velocity_verlet", "rk4", "implicit_euler", "adaptive"};
  for (const char* scene : {"incline_30", "plain_s1"}) {
    gp << "set title '" << scene << (std::string(scene) == "incline_30" ? " (a = 3.8111 m/s^2)" : " (v = 1.1111 m/s at 5 s)")
       << "'\nplot ";
    bool first = true;
    int pt = 1;
    for (const char* fid : {"rim20", "rim160", "circle"}) {
      int lt = 1;
      for (const char* integ : integrators) {
        const std::string file = dir + "/wp_" + scene + "_" + integ + "_" + fid + ".dat";
        std::ofstream d(file);
        int n = 0;
        for (const Result& r : rep.cells)
          if (r.scene == scene && r.healthy && integ == std::string(integratorName(r.setting.integrator)) &&
              fid == std::string(fidelityName(r.setting.fidelity)) && r.simPerWall() > 0) {
            d << 1.0 / r.simPerWall() << ' ' << std::max(r.error, 1e-12) << '\n';
            ++n;
          }
        if (n > 0) {
          gp << (first ? "" : ", ") << "'" << file << "' using 1:2 with linespoints lt " << lt << " pt " << pt
             << " title '" << integ << " " << fid << "'";
          first = false;
        }
        ++lt;
      }
      pt += 2;
    }
    gp << "\n";
  }
  gp << "unset multiplot\n";

  // stability map: largest stable dt against ground stiffness, with theory
  gp << "set terminal pngcairo noenhanced size 1000,650 font 'sans,10'\nset output '" << img << "/stability_map.png'\n"
     << "set logscale xy\nset grid\nset key top right\nset title 'largest stable dt, 1 kg resting on a penalty ground'\n"
     << "set xlabel 'ground stiffness k [N/m]'\nset ylabel 'largest stable dt [s]'\nset format x '%.0e'\nset format y '%.0e'\n"
     << "plot 2/sqrt(x) with lines lt 1 dt 2 title 'theory 2/omega (symplectic Euler, Verlet)', "
     << "2*sqrt(2)/sqrt(x) with lines lt 3 dt 2 title 'theory 2.83/omega (RK4)'";
  int lt = 1;
  for (const char* integ : {"semi_implicit_euler", "velocity_verlet", "rk4"}) {
    const std::string file = dir + "/stab_" + integ + ".dat";
    std::ofstream d(file);
    for (const StabilityRow& s : rep.stability)
      if (s.family == "ground_stiffness" && integ == std::string(integratorName(s.integrator)) && std::isfinite(s.largest_dt))
        d << s.omega * s.omega << ' ' << s.largest_dt << '\n';
    gp << ", '" << file << "' using 1:2 with points lt " << lt << " pt " << (lt * 2 + 3) << " ps 1.5 title '" << integ
       << " measured'";
    lt += 1;
  }
  gp << "\n";
  if (!rep.road.empty()) gp << roadPlotScript(rep, dir, img);
  const std::string script = dir + "/plots.gp";
  std::ofstream(script) << gp.str();
  if (std::system(("gnuplot " + script).c_str()) != 0) std::fprintf(stderr, "gnuplot failed: %s\n", script.c_str());
}

// The document ends in hand-written sections (observed orders, presets,
// refused combinations) that no run of the sweep produces: everything after
// this line is carried over from the file being replaced.
const char* const kHandWritten = "<!-- Everything below this line is written by hand; tradeoff keeps it. -->";

namespace {

// The hand-written end of the document at `path` (from kHandWritten on), or
// nothing.
std::string handWrittenPart(const std::string& path) {
  std::ifstream old(path);
  std::stringstream ss;
  ss << old.rdbuf();
  const std::string text = ss.str();
  const auto at = text.find(kHandWritten);
  return at != std::string::npos ? text.substr(at) : std::string();
}

void writeIntro(const Report& rep, std::ostream& md) {
  md << "# Accuracy, cost and stability of the integrators and wheel models\n\n"
     << "Generated by `" << rep.command << "` (builds `bench/accuracy/tradeoff` and runs it; "
     << fmt("%.0f", rep.total_wall_seconds) << " s on " << rep.jobs
     << " worker threads). Every number below comes from that run; the raw cells are in "
        "`" << rep.out_dir << "/tradeoff.csv`, `" << rep.out_dir << "/stability.csv` and (the sedan's manoeuvres) `"
     << rep.out_dir << "/road.csv`.\n\n"
     << "Cost is measured two ways: **sim-s/wall-s**, simulated seconds per wall second on one thread "
        "(the sweep runs " << rep.jobs << " cells at once on a shared machine, so treat it as +-20%), and "
        "**evals/sim-s**, force evaluations per simulated second (exact, machine independent).\n\n"
     << "Settings: `dt` is the fixed step; the adaptive Bogacki-Shampine 3(2) runs at an output step of "
        "0.01 s and is labelled by its tolerance. Wheel models: `rimN`, the report's ring of N rim points on "
        "rim springs; `circle`, the exact circle contact with a bearing coupling. Car scenes use the report's "
        "car and ground (2000 N/m) with 20 N s/m ground damping.\n\n";
}

void writeScenes(const Report& rep, std::ostream& md) {
  md << "## Scenes\n\n| scene | answer the error is measured against |\n|---|---|\n";
  for (const Scene& s : rep.scenes) md << "| " << s.name << " | " << s.answer << " |\n";
  md << "\nThe experiments (`exp_*`) are the report's four scenes (plain coast, 30 degree downhill, "
        "10 degree uphill with 1.5 N m drive, cosine valley); their error is the relative difference in "
        "distance travelled against RK4 at dt 2e-5 with the same wheel model.\n\n";
}

// the healthy cell of `scene` within `bound` with the most simulated
// seconds per wall second
const Result* fastestWithin(const std::vector<Result>& cells, const std::string& scene, double bound) {
  const Result* best = nullptr;
  for (const Result& r : cells)
    if (r.scene == scene && r.healthy && r.error <= bound && (!best || r.simPerWall() > best->simPerWall())) best = &r;
  return best;
}

// fastest setting under each error threshold
void writeFastest(const Report& rep, std::ostream& md) {
  md << "## Fastest setting within an error bound\n\n"
     << "For each scene the setting with the most simulated seconds per wall second among the healthy cells "
        "within the bound (parked_20: creep in metres).\n\n"
     << "| scene | bound | setting | wheels | error | sim-s/wall-s | evals/sim-s |\n|---|---|---|---|---|---|---|\n";
  for (const Scene& s : rep.scenes) {
    const bool absolute = s.name == "parked_20";
    const std::vector<double> bounds = absolute ? std::vector<double>{1e-6} : std::vector<double>{2e-2, 5e-3, 1e-3, 1e-4};
    for (double b : bounds) {
      const Result* best = fastestWithin(rep.cells, s.name, b);
      md << "| " << s.name << " | " << (absolute ? fmt("%.0e m", b) : fmt("%.1g%%", 100 * b)) << " | ";
      if (!best) { md << "none in the sweep | | | | |\n"; continue; }
      md << best->setting.label() << " | " << (best->uses_fidelity ? fidelityName(best->setting.fidelity) : "-") << " | "
         << errorText(*best) << " | " << fmt("%.0f", best->simPerWall()) << " | " << fmt("%.0f", best->evalsPerSim())
         << " |\n";
    }
  }
  md << "\nFor comparison (physics notes, same scenes): MuJoCo 2.2.2 runs the two reference scenes at 76-118 "
        "sim-s/wall-s (dt 2 ms) and Bullet 3.24 at 270-330 (dt 1/240 s), both within 1e-4 relative error.\n\n";
}

// a scene without wheels: a row per setting
void writePlainCells(const Report& rep, const Scene& s, const std::vector<Setting>& settings, std::ostream& md) {
  md << "| setting | error | sim-s/wall-s | evals/sim-s |\n|---|---|---|---|\n";
  for (const Setting& st : settings)
    if (const Result* r = find(rep.cells, s.name, st, Fidelity::Rim20))
      md << "| " << st.label() << " | " << errorText(*r) << " | " << fmt("%.0f", r->simPerWall()) << " | "
         << fmt("%.0f", r->evalsPerSim()) << " |\n";
}

// the wheel models the sweep ran `scene` with (indices into kFids)
std::vector<int> fidelityColumns(const std::vector<Result>& cells, const std::string& scene) {
  std::vector<int> cols;
  for (int f = 0; f < 5; ++f)
    for (const Result& r : cells)
      if (r.scene == scene && r.setting.fidelity == kFidValues[f]) { cols.push_back(f); break; }
  return cols;
}

// a car scene: a row per setting, a column per wheel model
void writeFidelityCells(const Report& rep, const Scene& s, const std::vector<Setting>& settings, std::ostream& md) {
  md << "| setting |";
  const std::vector<int> cols = fidelityColumns(rep.cells, s.name);
  for (int f : cols) md << ' ' << kFids[f] << " |";
  md << "\n|---|";
  for (size_t i = 0; i < cols.size(); ++i) md << "---|";
  md << "\n";
  for (const Setting& st : settings) {
    md << "| " << st.label() << " |";
    for (int f : cols) {
      const Result* r = find(rep.cells, s.name, st, kFidValues[f]);
      if (!r) md << " - |";
      else if (!r->healthy) md << " " << errorText(*r) << " |";
      else md << " " << errorText(*r) << "<br>" << fmt("%.0f", r->simPerWall()) << " |";
    }
    md << "\n";
  }
}

void writeEveryCell(const Report& rep, std::ostream& md) {
  md << "## Every cell\n\nError (relative unless marked m) and, below it, sim-s/wall-s.\n\n";
  for (const Scene& s : rep.scenes) {
    md << "### " << s.name << "\n\n" << s.answer << "\n\n";
    const auto settings = settingsOf(rep.cells, s.name);
    if (!s.uses_fidelity) writePlainCells(rep, s, settings, md);
    else writeFidelityCells(rep, s, settings, md);
    md << "\n";
  }
}

void writeStability(const Report& rep, std::ostream& md) {
  md << "## Stability map\n\n![stability map](img/stability_map.png)\n\n"
     << "Largest stable dt by bisection (to 2%). Theory: omega dt < 2 for symplectic Euler and Verlet, "
        "< 2 sqrt(2) = 2.83 for RK4, linear and undamped. `any tried` means stable up to the largest step "
        "probed (the implicit Euler is unconditionally stable; the adaptive method substeps). Resting-mass "
        "probes count as unstable once the 1% perturbation grows 20x or the health check fails (without the "
        "growth test, RK4 runs on to omega dt 2.96 without lift-off: its stages leave the one-sided ground, "
        "which saturates the growth); car probes when the health check fails within 2 s. The adaptive method runs the probes at tolerance 1e-4: on the stiffest grounds the 1% perturbation (1e-9 m at 1e8 N/m) lies far below that tolerance, so its finite limit there is the controller accepting growth it cannot see, not an instability.\n\n"
     << "| family | parameter | integrator | largest stable dt | theory dt | omega dt at the limit | note |\n"
     << "|---|---|---|---|---|---|---|\n";
  for (const StabilityRow& s : rep.stability)
    md << "| " << s.family << " | " << s.parameter << " | " << integratorName(s.integrator) << " | "
       << dtText(s.largest_dt) << " | " << (s.theory_dt > 0 && std::isfinite(s.theory_dt) ? fmt("%.3g", s.theory_dt) : "-")
       << " | " << (s.omega > 0 && std::isfinite(s.largest_dt) && s.largest_dt > 0 ? fmt("%.2f", s.omega * s.largest_dt) : "-")
       << " | " << s.note << " |\n";
}

void writeHours(const Report& rep, std::ostream& md) {
  if (rep.hours.empty()) return;
  md << "\n## An hour of simulated time\n\nAt the cheapest setting within 2% on plain_s1 with the continuous wheel.\n\n"
     << "| scene | setting | healthy | wall s | sim-s/wall-s | outcome |\n|---|---|---|---|---|---|\n";
  for (const HourRun& h : rep.hours)
    md << "| " << h.scene << " | " << h.setting << " | " << (h.healthy ? "yes" : "no (" + h.status + ")") << " | "
       << fmt("%.1f", h.wall_seconds) << " | " << fmt("%.0f", h.sim_per_wall) << " | " << h.outcome << " |\n";
}

void writeRegenerate(const Report& rep, std::ostream& md) {
  md << "\n## Regenerate\n\n```\n" << rep.command << "\n```\n\n"
     << "The whole run took " << fmt("%.0f", rep.total_wall_seconds) << " s of wall time on " << rep.jobs
     << " worker threads (of which the sedan's manoeuvres " << fmt("%.0f", rep.road_wall_seconds) << " s); "
     << "the machine's load at the time sets it.\n\n";
}

}  // namespace

void writeMarkdown(const Report& rep, const std::string& path) {
  const std::string kept = handWrittenPart(path);
  std::ofstream md(path);
  writeIntro(rep, md);
  writeScenes(rep, md);
  writeFastest(rep, md);
  md << "## Work-precision\n\n![work-precision](img/work_precision.png)\n\n";
  if (!rep.road.empty()) writeRoadMarkdown(rep, md);
  writeEveryCell(rep, md);
  writeStability(rep, md);
  writeHours(rep, md);
  writeRegenerate(rep, md);
  md << (kept.empty() ? std::string(kHandWritten) + "\n" : kept);
}

}  // namespace groundsim::accuracy
