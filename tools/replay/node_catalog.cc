#include "tools/replay/node_catalog.h"

#ifdef NADIR_HAVE_TRACKER
#include "processes/tracker/tracker_node.h"
#endif
#ifdef NADIR_HAVE_VO_SOLVER
#include "processes/vo_solver/vo_solver_node.h"
#endif
#ifdef NADIR_HAVE_YAW_FUSION
#include "processes/yaw_fusion/yaw_fusion_node.h"
#endif
#ifdef NADIR_HAVE_MAP_MATCHER
#include "processes/map_matcher/map_matcher_node.h"
#endif
#ifdef NADIR_HAVE_FOXGLOVE
#include "processes/foxglove/foxglove_node.h"
#endif

namespace nadir {

void register_all_nodes(NodeRegistry& registry) {
#ifdef NADIR_HAVE_TRACKER
  register_tracker_node(registry);
#endif
#ifdef NADIR_HAVE_VO_SOLVER
  register_vo_solver_node(registry);
#endif
#ifdef NADIR_HAVE_YAW_FUSION
  register_yaw_fusion_node(registry);
#endif
#ifdef NADIR_HAVE_MAP_MATCHER
  register_map_matcher_node(registry);  // needs a map: map_matcher.orthophoto and .dem
#endif
#ifdef NADIR_HAVE_FOXGLOVE
  register_foxglove_node(registry);  // watch a replay in Foxglove; publishes only STATUS
#endif
  (void)registry;
}

}  // namespace nadir
