// Choices by content: a pilot is paid once per scenario. A long-running
// server (sessions) and make_vec keep the choices they made, keyed by what
// decides a choice: the validated document (its `accuracy` section and
// tolerance included), the contents of the files it read (heightfield,
// friction map) and the pilot's options. The pilot is deterministic (a count
// of force evaluations, not a timing), so a choice taken from the cache is
// the choice a new pilot would make. docs/accuracy.md, "The pilot's cost".
#pragma once

#include <cstddef>
#include <list>
#include <mutex>
#include <string>
#include <utility>

#include "accuracy/pilot.hpp"

namespace groundsim::accuracy {

class ChoiceCache {
 public:
  // at most `entries` choices, and at most `file_bytes` of ground files kept
  // alive through them (a choice's scenario shares the scene's heightfield)
  explicit ChoiceCache(std::size_t entries = 32, std::size_t file_bytes = std::size_t{128} << 20);

  // chooseSettings(s, tolerance, o), or the choice made before for the same
  // content (Choice::from_cache set, pilot_wall_seconds the lookup's)
  Choice choose(const scenario::Scenario& s, double tolerance, const PilotOptions& o);

  std::size_t size() const;
  // the process's own: what sessions and make_vec share
  static ChoiceCache& shared();

 private:
  struct Entry {
    std::string key;
    Choice choice;
    std::size_t file_bytes = 0;
  };
  mutable std::mutex mutex_;
  std::list<Entry> entries_;  // most recently used first
  std::size_t max_entries_, max_file_bytes_, file_bytes_ = 0;
};

// The key: a SHA-256 over the document, the ground files' contents, the
// tolerance and the options.
std::string choiceKey(const scenario::Scenario& s, double tolerance, const PilotOptions& o);

}  // namespace groundsim::accuracy
