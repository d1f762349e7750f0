#include "accuracy/choice_cache.hpp"

#include <chrono>
#include <cstring>

#include "physics/ground/heightfield.hpp"
#include "physics/ground/surface_friction.hpp"
#include "scenario/assets.hpp"

namespace groundsim::accuracy {
namespace {

template <class T>
void addBytes(std::string& out, const T& x) {
  out.append(reinterpret_cast<const char*>(&x), sizeof x);
}

void addFloats(std::string& out, const std::vector<float>& v) {
  addBytes(out, v.size());
  out.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(float));
}

std::size_t fileBytes(const scenario::Scenario& s) {
  std::size_t n = 0;
  if (s.ground.heightfield) n += s.ground.heightfield->bytes();
  if (s.ground.friction_map) n += s.ground.friction_map->mu.size() * sizeof(float);
  return n;
}

}  // namespace

std::string choiceKey(const scenario::Scenario& s, double tolerance, const PilotOptions& o) {
  std::string bytes = s.document.dump();
  bytes.push_back('\0');
  if (const auto& h = s.ground.heightfield) {
    addBytes(bytes, h->nx());
    addBytes(bytes, h->ny());
    addBytes(bytes, h->cell());
    addBytes(bytes, h->x0());
    addBytes(bytes, h->y0());
    addFloats(bytes, h->coefficients());
  }
  if (const auto& f = s.ground.friction_map) {
    addBytes(bytes, f->nx);
    addBytes(bytes, f->ny);
    addBytes(bytes, f->cell);
    addBytes(bytes, f->x0);
    addBytes(bytes, f->y0);
    addFloats(bytes, f->mu);
  }
  addBytes(bytes, tolerance);
  addBytes(bytes, o.pilot_duration);
  addBytes(bytes, o.fallback_duration);
  addBytes(bytes, o.max_share);
  addBytes(bytes, o.scout_duration);
  addBytes(bytes, o.min_pilot_work);
  addBytes(bytes, o.max_pilot_steps);
  addBytes(bytes, o.max_work);
  addBytes(bytes, o.safety);
  addBytes(bytes, o.min_dt);
  addBytes(bytes, o.other_models);
  for (IntegratorKind k : o.integrators) addBytes(bytes, k);
  return scenario::sha256Hex(bytes);
}

ChoiceCache::ChoiceCache(std::size_t entries, std::size_t file_bytes)
    : max_entries_(entries), max_file_bytes_(file_bytes) {}

ChoiceCache& ChoiceCache::shared() {
  static ChoiceCache cache;
  return cache;
}

std::size_t ChoiceCache::size() const {
  std::lock_guard<std::mutex> lk(mutex_);
  return entries_.size();
}

Choice ChoiceCache::choose(const scenario::Scenario& s, double tolerance, const PilotOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  const std::string key = choiceKey(s, tolerance, o);
  {
    std::lock_guard<std::mutex> lk(mutex_);
    for (auto it = entries_.begin(); it != entries_.end(); ++it)
      if (it->key == key) {
        entries_.splice(entries_.begin(), entries_, it);
        Choice c = it->choice;
        c.from_cache = true;
        c.pilot_wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        return c;
      }
  }
  // two creates of one new scenario at once each run the pilot (a worker
  // does not wait on another's): the same choice, kept once
  Choice c = chooseSettings(s, tolerance, o);
  const std::size_t bytes = fileBytes(s);
  if (bytes > max_file_bytes_ || max_entries_ == 0) return c;
  std::lock_guard<std::mutex> lk(mutex_);
  for (const Entry& e : entries_)
    if (e.key == key) return c;
  entries_.push_front(Entry{key, c, bytes});
  file_bytes_ += bytes;
  while (entries_.size() > max_entries_ || file_bytes_ > max_file_bytes_) {
    file_bytes_ -= entries_.back().file_bytes;
    entries_.pop_back();
  }
  return c;
}

}  // namespace groundsim::accuracy
