// Hand-drawn floor plans and synthetic voxel maps for the rooms tests.
#pragma once

#include <algorithm>
#include <cstdint>

#include "core/image.h"
#include "core/voxel_grid.h"
#include "core/voxel_key.h"
#include "rooms/floor_plan.h"

namespace semvox::testing {

// A grey map (0 occupied, 255 free) at 0.05 m per pixel.
struct GreyMap {
  Image<uint8_t> image;
  explicit GreyMap(int w, int h) : image(w, h, 1, 0) {}
  // Fills [x0, x1) x [y0, y1) in metres (x right, y down the image) with `value`.
  void Fill(double x0, double y0, double x1, double y1, uint8_t value) {
    for (int y = std::max(0, int(y0 / 0.05 + 0.5)); y < std::min(image.height, int(y1 / 0.05 + 0.5)); ++y)
      for (int x = std::max(0, int(x0 / 0.05 + 0.5)); x < std::min(image.width, int(x1 / 0.05 + 0.5)); ++x)
        image.at(x, y) = value;
  }
};

// Two 4 m x 3 m rooms side by side, joined by a door `door_m` wide in a 0.1 m wall at x = 4.5 m.
inline GreyMap TwoRoomsWithDoor(double door_m = 0.9) {
  GreyMap m(200, 90);                        // 10 m x 4.5 m.
  m.Fill(0.5, 0.5, 9.5, 3.5, 255);           // Free space.
  m.Fill(4.45, 0.5, 4.55, 3.5, 0);           // The wall between the rooms...
  m.Fill(4.45, 1.5, 4.55, 1.5 + door_m, 255);  // ...with its door.
  return m;
}

// A voxel grid at 0.05 m with its lower corner at the origin: floor layer at z = 0, ceiling layer at
// `ceiling_m`, free space between; walls are added with Wall().
struct VoxelRooms {
  VoxelGrid grid;
  double ceiling_m;
  VoxelRooms(int nx, int ny, double ceiling = 2.5)
      : grid(0.05, {int(kKeyOffset), int(kKeyOffset), int(kKeyOffset)}, {nx, ny, int(ceiling / 0.05) + 2}),
        ceiling_m(ceiling) {
    const auto& d = grid.dims();
    for (int z = 0; z < d[2]; ++z)
      for (int y = 0; y < d[1]; ++y)
        for (int x = 0; x < d[0]; ++x) {
          const bool border = x == 0 || y == 0 || x == d[0] - 1 || y == d[1] - 1;
          const bool shell = z == 0 || z == int(ceiling / 0.05);
          grid.set_state(grid.Index(x, y, z), border || z > int(ceiling / 0.05)
                                                  ? VoxelState::kUnknown
                                                  : shell ? VoxelState::kOccupied : VoxelState::kFree);
        }
  }
  // Occupies cells [x0, x1) x [y0, y1) from z0 to z1 metres (cell indices in x/y).
  void Box(int x0, int y0, int x1, int y1, double z0_m, double z1_m, VoxelState s = VoxelState::kOccupied) {
    for (int z = int(z0_m / 0.05); z < std::min(grid.dims()[2], int(z1_m / 0.05)); ++z)
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) grid.set_state(grid.Index(x, y, z), s);
  }
};

}  // namespace semvox::testing
