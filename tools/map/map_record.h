#pragma once
// map.json: what nadir_map simulate did -- the run it mapped, the grid and
// CRS, the season transform's parameters and the changed patches -- so a
// study can say exactly which map a result was matched against. No times
// or paths of the machine: the same inputs give the same bytes.

#include <string>

#include "processes/sim/flight_profile.h"
#include "tools/map/simulated_map.h"

namespace nadir::map {

std::string map_record_json(const sim::FlightProfile& profile, uint64_t seed, const SimulatedMapOptions& options,
                            const SimulatedMap& map);

}  // namespace nadir::map
