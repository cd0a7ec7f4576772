#include "rooms/r2v_layout.h"

#include <map>

#include "core/file_util.h"
#include "core/labels.h"
#include "rooms/r2v_plan.h"

namespace semvox {

Result<PlanLayout> LayoutOfR2vPlan(const std::string& path, int* unclosed) {
  Result<R2vPlan> plan = ReadR2vPlan(path);
  if (!plan.ok()) return plan.status();
  const double s = plan->metres_per_unit;
  PlanLayout layout;
  R2vRooms rooms = RasteriseR2vRooms(*plan, layout.resolution_m);
  if (rooms.ids.data.empty())
    return Status::InvalidInput(FileError(path, "too large to rasterise at 0.05 m (over 1 km across at its door scale)",
                                          "check the plan's coordinates"));
  layout.rooms = std::move(rooms.ids);
  layout.room_type = std::move(rooms.type_id);
  layout.origin = Eigen::Vector2d(rooms.origin_m, rooms.origin_m);
  const std::map<std::string, int> fixture = {{"toilet", nyu40::kToilet}, {"bathtub", nyu40::kBathtub},
                                              {"washing_basin", nyu40::kSink}, {"cooking_counter", nyu40::kCounter}};
  *unclosed = 0;
  for (const R2vItem& it : plan->items) {
    const Eigen::Vector2d a(it.x0 * s, it.y0 * s), b(it.x1 * s, it.y1 * s);
    if (it.category == "wall") layout.walls.push_back({a, b});
    else if (it.category == "door") layout.doors.push_back({a, b});
    else if (const auto f = fixture.find(it.category); f != fixture.end()) layout.fixtures.push_back({a, b, f->second});
    else if (IsR2vRoomLabel(it.category)) {
      const Eigen::Vector2d c = 0.5 * (a + b) - layout.origin;
      const int col = int(c.x() / layout.resolution_m), row = int(c.y() / layout.resolution_m);
      const bool inside = col >= 0 && row >= 0 && col < layout.rooms.width && row < layout.rooms.height;
      if (inside && layout.rooms.at(col, row) == 0) ++*unclosed;
    }
  }
  return layout;
}

}  // namespace semvox
