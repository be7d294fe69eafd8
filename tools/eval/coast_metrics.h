#pragma once
// Where the estimate coasted (POSE flag COASTING: VO out, the position held
// on the last velocity, the height on the altimeter where it can) and what
// each coast added to the error: the error at its last coasting pose less
// the error at the pose before it.

#include <cstdint>
#include <vector>

namespace nadir {

struct EvalSample;  // trajectory_metrics.h

struct CoastEpisode {
  double start_s = 0;     // the pose before the first coasting one (the last VO pose, or a gap pose), since the first pose
  double duration_s = 0;  // from there to the last coasting pose
  double added_h_m = 0;   // horizontal error vector at the end less the one at the start, its length
  double added_v_m = 0;   // vertical (down) error at the end less the one at the start, signed
  double error_h_m = 0;   // horizontal error at the end
  double sigma_h_m = 0;   // reported horizontal sigma at the end
};

// Each maximal run of samples carrying `coasting_flag`, in time order. A run
// that starts at the first sample starts there (no pose before it).
std::vector<CoastEpisode> coast_episodes(const std::vector<EvalSample>& samples, int32_t coasting_flag);

}  // namespace nadir
