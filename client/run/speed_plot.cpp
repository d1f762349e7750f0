#include "speed_plot.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

extern char** environ;

namespace groundsim::cli {
namespace {

// gnuplot single-quoted string: only ' needs escaping, as ''
std::string quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\'') out += '\'';
    out += c;
  }
  return out + "'";
}

std::string script(const SpeedPlot& p) {
  std::ostringstream s;
  s << "set terminal pngcairo size 1000,560 noenhanced\n"
    << "set output " << quoted(p.png_path) << "\n"
    << "set datafile separator ','\n"
    << "set title " << quoted(p.title) << "\n"
    << "set xlabel " << quoted("frame (" + std::to_string(static_cast<long>(p.output_rate + 0.5)) +
                               " per second)") << "\n"
    << "set ylabel 'speed of the body (m/s)'\n"
    << "set grid\nset key top right\n"
    << "plot ";
  // columns (telemetry_csv): 1 t, 8 speed, 9 vehicle; one row per vehicle
  // per frame, so each line keeps only its own vehicle's rows
  for (size_t i = 0; i < p.vehicles.size(); ++i) {
    if (i) s << ", \\\n     ";
    s << quoted(p.csv_path) << " skip 1 using ($1*" << p.output_rate << "):(strcol(9) eq "
      << quoted(p.vehicles[i]) << " ? $8 : NaN) with lines lw 1.5 title " << quoted(p.vehicles[i]);
  }
  s << "\n";
  return s.str();
}

}  // namespace

std::string drawSpeedPlot(const SpeedPlot& p) {
  const char* tmpdir = std::getenv("TMPDIR");
  std::string path = std::string(tmpdir && *tmpdir ? tmpdir : "/tmp") + "/groundsim-plot-XXXXXX";
  const int fd = mkstemp(path.data());
  if (fd < 0) return "cannot create a temporary gnuplot script: " + std::string(std::strerror(errno));
  close(fd);
  {
    std::ofstream out(path);
    out << script(p);
    if (!out) {
      std::remove(path.c_str());
      return "cannot write the gnuplot script " + path;
    }
  }
  // spawn without a shell: file names need no shell quoting
  char* argv[] = {const_cast<char*>("gnuplot"), path.data(), nullptr};
  pid_t pid = 0;
  const int err = posix_spawnp(&pid, "gnuplot", nullptr, nullptr, argv, environ);
  if (err != 0) {
    std::remove(path.c_str());
    return "cannot run gnuplot (" + std::string(std::strerror(err)) + "); install gnuplot-nox";
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  std::remove(path.c_str());
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) return "gnuplot failed (see its message above)";
  return {};
}

}  // namespace groundsim::cli
