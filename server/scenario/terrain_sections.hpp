// The ground section's terrain parts, read through the ground's
// ObjectReader: a heightfield's samples (heightfield_section.cpp) and
// friction by place, for any ground kind (friction_section.cpp).
#pragma once

#include <optional>

#include "scenario/file_access.hpp"
#include "scenario/ground_spec.hpp"
#include "scenario/object_reader.hpp"
#include "scenario/terrain_loader.hpp"

namespace groundsim::scenario {

// Keys of a heightfield ground (besides "type") and of the friction parts.
extern const std::vector<std::string> kHeightfieldKeys;
extern const std::vector<std::string> kFrictionKeys;

// file, heights, cell_size, origin, height_scale, height_offset: fills
// g.heightfield, or records issues.
void readHeightfield(ObjectReader& r, GroundSpec& g, const FileAccess& files);
// friction_patches, friction_map (both optional).
void readSurfaceFriction(ObjectReader& r, GroundSpec& g, const FileAccess& files);

// The grid named by `file_key` (a PNG or CSV under `files`) or given inline
// as rows under `inline_key` (exactly one of the two); nullopt with issues
// recorded when neither, both, or broken. `bound` limits each value read
// inline or from a CSV.
std::optional<Grid> readGridSource(ObjectReader& r, const std::string& file_key, const std::string& inline_key,
                                   const FileAccess& files, double bound);

// Whether a PNG's scale key applies: the grid is a PNG, or (when it could
// not be read) the file named under file_key is called *.png.
bool scaledGrid(ObjectReader& r, const std::optional<Grid>& grid, const std::string& file_key);

}  // namespace groundsim::scenario
