// The options of `record` and `convert` that choose how the state streams'
// numbers are written (protocol/message_json.hpp, docs/logging.md, Size):
// by default each quantity to its own decimals; --exact every double
// exactly; --digits N to N significant digits.
#pragma once

#include <memory>

#include <CLI/CLI.hpp>

#include "protocol/message_json.hpp"

namespace groundsim::record {

struct PrecisionOptions {
  bool exact = false;
  int digits = 0;  // 0: not given
};

// Adds --exact and --digits to `cmd`; call applyPrecision(o) in its callback.
inline void addPrecisionOptions(CLI::App* cmd, PrecisionOptions& o) {
  auto* exact = cmd->add_flag("--exact", o.exact,
                              "every double of the states exactly (the shortest text that reads back as it; "
                              "about 3.5 times the default's size)");
  cmd->add_option("--digits", o.digits,
                  "the states' numbers to N significant digits instead of each quantity's decimals (17: --exact)")
      ->check(CLI::Range(1, 17))
      ->excludes(exact);
}

inline void applyPrecision(const PrecisionOptions& o) {
  if (o.exact || o.digits == 17) setPrecision(Precision::Exact);
  else if (o.digits > 0) setPrecision(Precision::Digits, o.digits);
  else setPrecision(Precision::Fields);
}

}  // namespace groundsim::record
