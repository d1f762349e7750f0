// Output for the sedan's manoeuvres: CSV, the work-precision plot, the
// markdown section of docs/accuracy.md and the road-car preset choice.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <ostream>
#include <sstream>

#include "report.hpp"

namespace groundsim::accuracy {
namespace {

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

bool same(const Setting& a, const Setting& b) {
  return a.integrator == b.integrator && a.dt == b.dt && a.tolerance == b.tolerance;
}

// The road-car presets and the bound each stands for (scenario/presets.cpp
// takes its road-car settings from the table this writes).
struct Bound {
  const char* preset;
  double bound;
};
constexpr Bound kBounds[] = {{"fast", 5e-2}, {"balanced", 1e-2}, {"accurate", 1e-3}};

std::string pct(double b) { return fmt("%g%%", 100 * b); }

std::string errorCell(const RoadRun& r) { return r.healthy ? fmt("%.2e", r.path_max) : "diverged (" + r.status + ")"; }

}  // namespace

RoadChoice roadChoice(const Report& rep, double bound, const std::string& manoeuvre) {
  return roadChoice(rep.road, bound, manoeuvre);
}

RoadChoice roadChoice(const std::vector<RoadRun>& runs, double bound, const std::string& manoeuvre) {
  RoadChoice best;
  std::vector<Setting> seen;
  for (const RoadRun& r : runs) {
    if (std::any_of(seen.begin(), seen.end(), [&](const Setting& s) { return same(s, r.setting); })) continue;
    seen.push_back(r.setting);
    RoadChoice c;
    c.found = true;
    c.setting = r.setting;
    c.sim_per_wall = 1e300;
    int counted = 0;
    for (const RoadRun& o : runs) {
      if (!same(o.setting, r.setting) || (!manoeuvre.empty() && o.manoeuvre != manoeuvre)) continue;
      ++counted;
      if (!o.healthy || !(o.path_max <= bound)) { c.found = false; break; }
      if (o.path_max >= c.worst) { c.worst = o.path_max; c.worst_in = o.manoeuvre; }
      c.evals_per_sim = std::max(c.evals_per_sim, o.evalsPerSim());
      c.sim_per_wall = std::min(c.sim_per_wall, o.simPerWall());
    }
    if (!c.found || counted == 0) continue;
    // ties (semi-implicit Euler at dt and Verlet at 2 dt cost the same)
    // go to the smaller error, not to the noisy wall time: the choice must
    // come out the same on every run
    if (!best.found || c.evals_per_sim < best.evals_per_sim ||
        (c.evals_per_sim == best.evals_per_sim && c.worst < best.worst))
      best = c;
  }
  return best;
}

void writeRoadCsv(const Report& rep, const std::string& path) {
  std::ofstream f(path);
  f << "manoeuvre,integrator,dt,tolerance,healthy,status,key,key_error,path_rms,path_max,length,"
       "sim_seconds,wall_seconds,sim_per_wall,evaluations,evals_per_sim,tyre\n";
  std::vector<const RoadRun*> all;
  for (const RoadRun& r : rep.road) all.push_back(&r);
  for (const RoadRun& r : rep.stick) all.push_back(&r);
  for (const RoadRun* rp : all) {
    const RoadRun& r = *rp;
    f << r.manoeuvre << ',' << integratorName(r.setting.integrator) << ',' << r.setting.dt << ','
      << (r.setting.integrator == IntegratorKind::Adaptive ? r.setting.tolerance : 0.0) << ',' << r.healthy << ','
      << r.status << ',';
    if (r.healthy) f << r.key << ',' << r.key_error << ',' << r.path_rms << ',' << r.path_max << ',' << r.length;
    else f << ",,,,";  // a diverged cell has no figures: the CSV never carries NaN
    f << ',' << r.sim_seconds << ',' << r.wall_seconds << ',' << r.simPerWall() << ',' << r.evaluations << ','
      << r.evalsPerSim() << ',' << (r.stick_slip ? "stick_slip" : "magic_formula") << '\n';
  }
}

std::string roadPlotScript(const Report& rep, const std::string& dir, const std::string& img) {
  // work (force evaluations per simulated second) against the path's max
  // error, one panel per manoeuvre and one for the worst over all of them
  std::ostringstream gp;
  gp << "set terminal pngcairo noenhanced size 1500,900 font 'sans,10'\nset output '" << img
     << "/road_work_precision.png'\nset multiplot layout 2,3 title 'sedan manoeuvres: path error against a "
        "converged reference (RK4, dt "
     << kRoadRefDt << " s)'\nunset label\nset logscale xy\nset grid\nset key inside top right font ',8'\n"
     << "set xlabel 'force evaluations per simulated second (lower is cheaper)'\n"
     << "set ylabel 'max path error / path length'\nset format y '%.0e'\nset format x '%.0e'\n"
     << "set yrange [1e-12:1]\nset xrange [50:1e5]\n"
     << "set label 1 'errors below 1e-12 drawn at 1e-12; dashed: 5%, 1%, 0.1%' at graph 0.02, graph 0.04 font ',8'\n";
  const char* integrators[] = {"semi_implicit_euler", "velocity_verlet", "rk4", "implicit_euler", "adaptive"};
  std::vector<std::string> panels;
  for (const RoadManoeuvre& m : roadManoeuvres()) panels.push_back(m.name);
  panels.push_back("");  // worst over all
  for (const std::string& panel : panels) {
    gp << "set title '" << (panel.empty() ? "worst over the five manoeuvres" : panel) << "'\n";
    for (const Bound& b : kBounds)
      gp << "set arrow from graph 0, first " << b.bound << " to graph 1, first " << b.bound << " nohead dt 2 lw 1.5 lc rgb '#cc3333'\n";
    gp << "plot ";
    bool first = true;
    int lt = 1;
    for (const char* integ : integrators) {
      const std::string file = dir + "/road_" + (panel.empty() ? "worst" : panel) + "_" + integ + ".dat";
      std::ofstream d(file);
      int n = 0;
      std::vector<Setting> done;
      for (const RoadRun& r : rep.road) {
        if (integ != std::string(integratorName(r.setting.integrator))) continue;
        if (!panel.empty() && r.manoeuvre != panel) continue;
        if (std::any_of(done.begin(), done.end(), [&](const Setting& s) { return same(s, r.setting); })) continue;
        done.push_back(r.setting);
        // worst over the manoeuvres of this setting; skipped if any diverged
        double err = 0, evals = 0;
        bool ok = true;
        for (const RoadRun& o : rep.road)
          if (same(o.setting, r.setting) && (panel.empty() || o.manoeuvre == panel)) {
            ok = ok && o.healthy;
            err = std::max(err, o.path_max);
            evals = std::max(evals, o.evalsPerSim());
          }
        if (!ok || evals <= 0) continue;
        d << evals << ' ' << std::max(err, 1e-12) << '\n';
        ++n;
      }
      if (n > 0) {
        gp << (first ? "" : ", ") << "'" << file << "' using 1:2 with linespoints lt " << lt << " pt " << (2 * lt + 3)
           << " title '" << integ << "'";
        first = false;
      }
      ++lt;
    }
    gp << (first ? "1/0 notitle" : "") << "\nunset arrow\n";
  }
  gp << "unset multiplot\nunset label\n";
  return gp.str();
}

namespace {

// The section's opening: the manoeuvres, the reference and the tyre models.
void writeRoadIntro(std::ostream& md) {
  md << "## The sedan's manoeuvres\n\n"
     << "The road car of issue 9 (`configs/sedan.json`, Magic Formula tyres, mu 1.0) built through the scenario "
        "layer as `groundsim run` builds it, each manoeuvre driven by its control table (rows at multiples of "
        "80 ms, so every step in the grid applies them at the same instant). The path is the body's centre of "
        "mass every "
     << kRoadSample * 1e3
     << " ms; its error is the distance to the reference at the same instant, max and RMS over the run, "
        "divided by the reference's path length. The key figure's error is relative. The reference is RK4 at dt "
     << kRoadRefDt
     << " s (of the integrators, RK4 converges fastest where the right-hand side is smooth: at order 4 on the "
        "hill road and the bumps; on the step steer and the lane change every integrator is first order, "
        "since the steering angle moves once per step (its rate limit, like the controls, is applied per "
        "step), and on the braking run the ABS and brake clamp act per step too); how converged it is: the same errors of RK4 at dt "
     << 2 * kRoadRefDt << " s against it (the columns `ref: 2 dt vs dt`).\n\n"
     << "Tyre models: the Magic Formula (the tables above and below, and the presets) and the rigid stick-slip "
        "contact (`tyres.model: \"stick_slip\"`, its own section after the presets). The stick-slip tyre has no "
        "slip angle, so it does not give the declared cornering stiffnesses (its understeer gradient is 0, the "
        "yaw response kinematic until the friction limit), and its friction and brake impulses are sized by the "
        "step, so only semi-implicit Euler and velocity Verlet take it (RK4, implicit Euler and the adaptive "
        "method are refused at `/vehicles/i/tyres/model`); it is measured against its own converged reference, "
        "not the Magic Formula's. "
        "`physics.substeps` n at step dt integrates "
        "exactly as dt / n with the controls held for n substeps, so the step grid covers it. The ODE "
        "integrators run with `contact.friction_model: \"regularized\"` (they are refused with stick-slip); "
        "a road car's tyres do not use the ground's friction model, so nothing else changes.\n\n";
}

// Each manoeuvre's reference and how converged it is.
void writeRoadReferences(const Report& rep, std::ostream& md) {
  md << "| manoeuvre | what | path length m | key figure | reference | ref: 2 dt vs dt, path max | path rms | key |\n"
     << "|---|---|---|---|---|---|---|---|\n";
  const auto& ms = roadManoeuvres();
  for (size_t i = 0; i < ms.size() && i < rep.road_refs.size(); ++i) {
    const RoadReference& ref = rep.road_refs[i];
    md << "| " << ms[i].name << " | " << ms[i].what << " | " << fmt("%.1f", ref.run.length) << " | " << ms[i].key
       << " | " << (ref.run.healthy ? fmt("%.6g", ref.run.key) : "diverged (" + ref.run.status + ")") << " | "
       << (ref.half.healthy ? fmt("%.1e", ref.half.path_max) : "diverged") << " | " << fmt("%.1e", ref.half.path_rms)
       << " | " << fmt("%.1e", ref.half.key_error) << " |\n";
  }
}

// Per manoeuvre and bound, the cheapest setting within it.
void writeRoadFastest(const Report& rep, std::ostream& md) {
  md << "\n### Fastest setting within 0.1%, 1% and 5% of the reference path\n\n"
     << "Per manoeuvre, the cheapest healthy setting whose max path error is within the bound. Cheapest: the "
        "fewest force evaluations per simulated second (exact and machine independent; a road-car evaluation "
        "costs the same in every integrator, and implicit Euler's count includes its Jacobian's), ties broken "
        "by the smaller error. sim-s/wall-s is shown for scale only (one thread; "
     << rep.jobs << " cells ran at once on a machine shared with other work, so wall figures are +-50% or worse; "
        "the cells with 16 ms steps are so short that their figures are mostly noise).\n\n"
     << "| manoeuvre | bound | setting | path max | path rms | key error | evals/sim-s | sim-s/wall-s |\n"
     << "|---|---|---|---|---|---|---|---|\n";
  for (const RoadManoeuvre& m : roadManoeuvres())
    for (auto it = std::rbegin(kBounds); it != std::rend(kBounds); ++it) {
      const RoadChoice c = roadChoice(rep, it->bound, m.name);
      md << "| " << m.name << " | " << pct(it->bound) << " | ";
      const RoadRun* r = nullptr;
      for (const RoadRun& o : rep.road)
        if (c.found && o.manoeuvre == m.name && same(o.setting, c.setting)) r = &o;
      if (!r) { md << "none in the sweep | | | | | |\n"; continue; }
      md << r->setting.label() << " | " << fmt("%.2e", r->path_max) << " | " << fmt("%.2e", r->path_rms) << " | "
         << fmt("%.2e", r->key_error) << " | " << fmt("%.0f", r->evalsPerSim()) << " | "
         << fmt("%.0f", r->simPerWall()) << " |\n";
    }
}

// The road-car presets: the cheapest setting within each bound on every
// manoeuvre.
void writeRoadPresets(const Report& rep, std::ostream& md) {
  md << "\n### Road-car presets\n\n"
     << "`\"preset\"` on a scenario whose vehicles are all road cars takes these settings "
        "(`server/scenario/presets.cpp`; `tests/vehicle/road_preset_test.cpp` checks that the code's table "
        "is this one and that each preset keeps its bound on the braking run): the cheapest setting within "
        "the bound on every manoeuvre above.\n\n"
     << "| preset | bound | physics.integrator | physics.dt s | worst path error | in | evals/sim-s | sim-s/wall-s |\n"
     << "|---|---|---|---|---|---|---|---|\n";
  for (const Bound& b : kBounds) {
    const RoadChoice c = roadChoice(rep, b.bound);
    md << "| `" << b.preset << "` | " << pct(b.bound) << " | ";
    if (!c.found) { md << "none in the sweep | | | | | |\n"; continue; }
    md << integratorName(c.setting.integrator) << " | " << fmt("%g", c.setting.dt) << " | "
       << fmt("%.2e", c.worst) << " | " << c.worst_in << " | " << fmt("%.0f", c.evals_per_sim) << " | "
       << fmt("%.0f", c.sim_per_wall) << " |\n";
  }
}

// The work-precision plot and every road cell, manoeuvre by manoeuvre.
void writeRoadCells(const Report& rep, std::ostream& md) {
  md << "\n![sedan work-precision](img/road_work_precision.png)\n\n"
     << "Dashed lines: the bounds 5%, 1%, 0.1%. Diverged settings are left out of a panel; the adaptive "
        "method's points are its tolerances 1e-3 to 1e-6 at an output step of 8 ms.\n\n"
     << "### Every road cell\n\n";
  for (const RoadManoeuvre& m : roadManoeuvres()) {
    md << "#### " << m.name << "\n\n" << m.what << "; key figure: " << m.key << "\n\n"
       << "| setting | path max | path rms | key | key error | evals/sim-s | sim-s/wall-s |\n|---|---|---|---|---|---|---|\n";
    for (const RoadRun& r : rep.road) {
      if (r.manoeuvre != m.name) continue;
      md << "| " << r.setting.label() << " | " << errorCell(r) << " | ";
      if (r.healthy)
        md << fmt("%.2e", r.path_rms) << " | " << fmt("%.6g", r.key) << " | " << fmt("%.2e", r.key_error) << " | ";
      else
        md << " | | | ";
      md << fmt("%.0f", r.evalsPerSim()) << " | " << fmt("%.0f", r.simPerWall()) << " |\n";
    }
    md << "\n";
  }
}

}  // namespace

void writeRoadMarkdown(const Report& rep, std::ostream& md) {
  writeRoadIntro(md);
  writeRoadReferences(rep, md);
  writeRoadFastest(rep, md);
  writeRoadPresets(rep, md);
  writeStickSlipMarkdown(rep, md);
  writeRoadCells(rep, md);
}

void writeStickSlipMarkdown(const Report& rep, std::ostream& md) {
  if (rep.stick.empty()) return;
  const auto& ms = roadManoeuvres();
  md << "\n### The stick-slip tyre\n\n"
     << "The same manoeuvres with `tyres.model: \"stick_slip\"` on both axles (everything else as in "
        "`configs/sedan.json`). Reference: velocity Verlet at dt "
     << kStickRefDt
     << " s (RK4 is refused with this tyre), its convergence the same errors of Verlet at dt " << 2 * kStickRefDt
     << " s against it. The paths are not comparable with the Magic Formula's: with no slip angle the car "
        "steers kinematically (more yaw for the same steer), and ABS brakes at 95% of the static friction. "
        "The work-precision plot below is the Magic Formula's.\n\n"
     << "| manoeuvre | path length m | reference key | ref: 2 dt vs dt, path max | path rms | key |\n"
     << "|---|---|---|---|---|---|\n";
  for (size_t i = 0; i < ms.size() && i < rep.stick_refs.size(); ++i) {
    const RoadReference& ref = rep.stick_refs[i];
    md << "| " << ms[i].name << " | " << fmt("%.1f", ref.run.length) << " | "
       << (ref.run.healthy ? fmt("%.6g", ref.run.key) : "diverged (" + ref.run.status + ")") << " | "
       << (ref.half.healthy ? fmt("%.1e", ref.half.path_max) : "diverged") << " | " << fmt("%.1e", ref.half.path_rms)
       << " | " << fmt("%.1e", ref.half.key_error) << " |\n";
  }
  md << "\nFastest setting within each bound of its own reference (cheapest as above):\n\n"
     << "| manoeuvre | bound | setting | path max | path rms | key error | evals/sim-s | sim-s/wall-s |\n"
     << "|---|---|---|---|---|---|---|---|\n";
  std::vector<std::string> names;
  for (const RoadManoeuvre& m : ms) names.push_back(m.name);
  names.push_back("");  // every manoeuvre at once
  for (const std::string& name : names)
    for (auto it = std::rbegin(kBounds); it != std::rend(kBounds); ++it) {
      const RoadChoice c = roadChoice(rep.stick, it->bound, name);
      md << "| " << (name.empty() ? "all five" : name) << " | " << pct(it->bound) << " | ";
      if (!c.found) { md << "none in the sweep | | | | | |\n"; continue; }
      if (name.empty()) {
        md << c.setting.label() << " | " << fmt("%.2e", c.worst) << " (" << c.worst_in << ") | | | "
           << fmt("%.0f", c.evals_per_sim) << " | " << fmt("%.0f", c.sim_per_wall) << " |\n";
        continue;
      }
      const RoadRun* r = nullptr;
      for (const RoadRun& o : rep.stick)
        if (o.manoeuvre == name && same(o.setting, c.setting)) r = &o;
      md << r->setting.label() << " | " << fmt("%.2e", r->path_max) << " | " << fmt("%.2e", r->path_rms) << " | "
         << fmt("%.2e", r->key_error) << " | " << fmt("%.0f", r->evalsPerSim()) << " | "
         << fmt("%.0f", r->simPerWall()) << " |\n";
    }
  md << "\nEvery stick-slip cell (path max error; diverged settings named):\n\n| setting |";
  for (const RoadManoeuvre& m : ms) md << " " << m.name << " |";
  md << "\n|---|";
  for (size_t i = 0; i < ms.size(); ++i) md << "---|";
  md << "\n";
  std::vector<Setting> done;
  for (const RoadRun& r : rep.stick) {
    if (std::any_of(done.begin(), done.end(), [&](const Setting& s) { return same(s, r.setting); })) continue;
    done.push_back(r.setting);
    md << "| " << r.setting.label() << " |";
    for (const RoadManoeuvre& m : ms)
      for (const RoadRun& o : rep.stick)
        if (o.manoeuvre == m.name && same(o.setting, r.setting)) md << " " << errorCell(o) << " |";
    md << "\n";
  }
}

}  // namespace groundsim::accuracy
