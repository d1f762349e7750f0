// Output of the sweep: CSV of every cell, gnuplot data and scripts, and the
// markdown document docs/accuracy.md.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

#include "cell.hpp"
#include "road_scenes.hpp"
#include "scenes.hpp"
#include "stability_map.hpp"

namespace groundsim::accuracy {

struct HourRun {
  std::string scene, setting;
  bool healthy = false;
  std::string status;
  double wall_seconds = 0, sim_per_wall = 0;
  std::string outcome;  // what stayed right over the hour
};

// A manoeuvre's reference (RK4 at kRoadRefDt) and how converged it is: the
// same errors of RK4 at 2 kRoadRefDt against it.
struct RoadReference {
  RoadRun run;
  RoadRun half;  // at 2 kRoadRefDt, compared with run
};

struct Report {
  std::vector<Scene> scenes;  // analytic + experiments, for their descriptions
  std::vector<Result> cells;
  std::vector<StabilityRow> stability;
  std::vector<HourRun> hours;
  std::vector<RoadReference> road_refs;  // one per roadManoeuvres() entry
  std::vector<RoadRun> road;             // every manoeuvre x roadSettings()
  std::vector<RoadReference> stick_refs; // the same with the stick-slip tyre (its own reference)
  std::vector<RoadRun> stick;            // every manoeuvre x stickSlipSettings(), stick-slip tyre
  std::string command;
  std::string out_dir;  // where the CSV files went
  double total_wall_seconds = 0;
  double road_wall_seconds = 0;  // the manoeuvres' part of it
  int jobs = 1;
};

void writeCsv(const Report& r, const std::string& path);
void writeStabilityCsv(const Report& r, const std::string& path);
// gnuplot scripts + data under dir; runs gnuplot if present. Writes
// img_dir/work_precision.png and img_dir/stability_map.png.
void writePlots(const Report& r, const std::string& dir, const std::string& img_dir);
void writeMarkdown(const Report& r, const std::string& path);

// The sedan's manoeuvres (road_report.cpp): CSV, the work-precision plot
// (img_dir/road_work_precision.png, gnuplot script under dir), the markdown
// section, and the settings the road-car presets take from them.
void writeRoadCsv(const Report& r, const std::string& path);
std::string roadPlotScript(const Report& r, const std::string& dir, const std::string& img_dir);
void writeRoadMarkdown(const Report& r, std::ostream& md);
// The cheapest setting (fewest force evaluations per simulated second:
// machine independent, where wall time on a shared machine is not) whose
// path (max error) stays within `bound` of the reference on `manoeuvre`, or
// on every manoeuvre when it is empty.
struct RoadChoice {
  bool found = false;
  Setting setting;
  double worst = 0;         // largest path_max over the manoeuvres counted
  double evals_per_sim = 0; // the largest over them
  double sim_per_wall = 0;  // the smallest over them
  std::string worst_in;     // the manoeuvre with the largest error
};
RoadChoice roadChoice(const Report& r, double bound, const std::string& manoeuvre = "");
RoadChoice roadChoice(const std::vector<RoadRun>& runs, double bound, const std::string& manoeuvre = "");
// The stick-slip tyre's part of the road section: its references and the
// fastest settings within the bounds (also printed by `tradeoff --road-only`).
void writeStickSlipMarkdown(const Report& r, std::ostream& md);

}  // namespace groundsim::accuracy
