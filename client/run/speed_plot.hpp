// `groundsim run --plot`: speed of each vehicle per frame, as in the
// report's figures, drawn by gnuplot from the run's CSV.
#pragma once

#include <string>
#include <vector>

namespace groundsim::cli {

struct SpeedPlot {
  std::string csv_path;                 // written by the run (telemetry_csv columns)
  std::string png_path;
  std::vector<std::string> vehicles;    // one line each
  double output_rate = 50.0;            // Hz: frames per second on the x axis
  std::string title;
};

// Runs gnuplot (pngcairo terminal, as in Debian's gnuplot-nox). Returns an
// empty string on success, else the reason.
std::string drawSpeedPlot(const SpeedPlot& p);

}  // namespace groundsim::cli
