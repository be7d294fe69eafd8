#pragma once
// Is the inlier set of a frame pair one ground patch, or two depth layers (a
// lawn and tree tops, a roof and the street)? The solver's model is one plane:
// a second layer the outlier cut let in biases the translation while the
// residual can stay small. Each inlier's depth is triangulated from its two
// rays with the published motion and compared with its depth on the patch.

#include <vector>

namespace nadir::vo {

struct DepthLayerOptions {
  double min_fraction = 0.15;       // each layer holds at least this share of the inliers
  double min_separation = 0.05;     // layer means differ by this much relative depth, at least ...
  double min_separation_sigma = 5;  // ... and by this many pooled within-layer standard deviations
  // Throws std::invalid_argument naming the field and the allowed range.
  void Check() const;
};

// Relative depth offsets (triangulated / patch depth - 1) of the inliers.
// True when the best two-group split (least within-group sum of squares, each
// group at least min_fraction) is separated beyond both thresholds. One
// Gaussian cloud splits at about 2.7 sigma, so 5 sigma does not fire on noise.
bool split_into_depth_layers(std::vector<double> offsets, const DepthLayerOptions& options);

}  // namespace nadir::vo
