#pragma once
// The few places where the map shows another ground than the world the
// camera flies over (a field ploughed, a clearing, a new roof): seeded
// rectangles and discs whose albedo replaces the terrain's, covering about
// `area_fraction` of the map.

#include <cstdint>
#include <vector>

namespace nadir::map {

struct ChangedPatch {
  enum Shape { kRectangle, kDisc } shape = kRectangle;
  double north = 0.0, east = 0.0;  // centre, local metres
  double half_north = 0.0, half_east = 0.0;  // rectangle half sides; disc: radius in both
  double albedo = 128.0;  // mean of the new ground
  double grain = 0.0;     // amplitude of its texture (value noise, 5 m cells)
  uint32_t salt = 0;

  bool contains(double n, double e) const;
  double area_m2() const;
  double albedo_at(double n, double e) const;
};

// Patches inside local [north0, north1] x [east0, east1] until their summed
// area reaches area_fraction of it (rectangles 15-60 m a side, discs of
// 8-30 m radius); the same arguments give the same patches.
std::vector<ChangedPatch> make_changed_patches(double north0, double north1, double east0, double east1,
                                               double area_fraction, uint64_t seed);

// Looks patches up by 64 m cell: the map asks once per sub-sample.
class PatchIndex {
 public:
  PatchIndex(const std::vector<ChangedPatch>& patches, double north0, double east0);
  // The albedo of the last patch holding (n, e), or false when none does.
  bool albedo(double n, double e, double* value) const;

 private:
  static constexpr double kCellM = 64.0;
  const std::vector<ChangedPatch>& patches_;
  double north0_, east0_;
  int cells_n_ = 0, cells_e_ = 0;
  std::vector<std::vector<int>> cells_;
};

}  // namespace nadir::map
