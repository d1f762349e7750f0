// Output of the sweep: CSV of every cell, gnuplot data and scripts, and the
// markdown document docs/accuracy.md.
#pragma once

#include <string>
#include <vector>

#include "cell.hpp"
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

struct Report {
  std::vector<Scene> scenes;  // analytic + experiments, for their descriptions
  std::vector<Result> cells;
  std::vector<StabilityRow> stability;
  std::vector<HourRun> hours;
  std::string command;
  std::string out_dir;  // where the CSV files went
  double total_wall_seconds = 0;
  int jobs = 1;
};

void writeCsv(const Report& r, const std::string& path);
void writeStabilityCsv(const Report& r, const std::string& path);
// gnuplot scripts + data under dir; runs gnuplot if present. Writes
// img_dir/work_precision.png and img_dir/stability_map.png.
void writePlots(const Report& r, const std::string& dir, const std::string& img_dir);
void writeMarkdown(const Report& r, const std::string& path);

}  // namespace groundsim::accuracy
