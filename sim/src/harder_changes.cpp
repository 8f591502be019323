// The harder changes between visits (WorldOptions::season, construction, furniture, pass_traffic): each
// from a generator of its own, so that one switched on leaves the world and every other change as it was.
#include <random>

#include "world_changes.h"

namespace scan_context_loop {
namespace sim {

void harderChanges(const std::vector<PathPoint>& path, const std::vector<double>& times, const StreetRecord& record,
                   StreetKit* kit) {
  const WorldOptions& o = kit->options;
  // Each kind keyed like changed_world's changes: the seed mixed with a salt of its own.
  const auto keyed = [&](double strength, std::uint64_t salt, auto change) {
    if (!(strength > 0.0) || !(o.duration > 0.0)) return;
    Changes c;
    c.strength = strength;
    c.to = o.duration;
    c.salt = salt;
    std::mt19937 draws(static_cast<std::uint32_t>(mix(o.seed ^ salt)));
    const DrawFrom scoped(*kit, &draws);
    change(c);
  };
  keyed(o.season, 0x5EA5011EAF0FFull, [&](const Changes& c) { leafOff(record, c, kit); });
  keyed(o.construction, 0xB01D517E5C0A7ull, [&](const Changes& c) { addBuildingSites(c, kit); });
  keyed(o.furniture, 0xF0E17A3B6E4C1ull, [&](const Changes& c) { moveFurniture(record, c, kit); });
  keyed(o.pass_traffic, 0x9A55DE7517E5ull,
        [&](const Changes& c) { passDensity(path, times, record, c.strength, kit); });
}

}  // namespace sim
}  // namespace scan_context_loop
