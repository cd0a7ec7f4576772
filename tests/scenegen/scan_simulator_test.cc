// The simulated scanner: deterministic, labelled, noise as configured.
#include <gtest/gtest.h>

#include <cmath>

#include "core/labels.h"
#include "scenegen/apartment.h"
#include "scenegen/scan_simulator.h"

namespace semvox {
namespace {

Apartment Generate(uint64_t seed) {
  ApartmentOptions o;
  o.seed = seed;
  o.min_rooms = 2;
  o.max_rooms = 3;
  Result<Apartment> a = GenerateApartment(o);
  EXPECT_TRUE(a.ok());
  return std::move(a).value();
}

ScanSimulationOptions Coarse() {
  ScanSimulationOptions o;
  o.azimuth_steps = 180;
  o.elevation_steps = 90;
  return o;
}

TEST(ScanSimulator, SameSeedSameCloud) {
  const Apartment apt = Generate(11);
  Result<PointCloud> a = SimulateScan(apt, Coarse()), b = SimulateScan(apt, Coarse());
  ASSERT_TRUE(a.ok()) << a.status().message();
  ASSERT_TRUE(b.ok());
  ASSERT_GT(a->points.size(), 5000u);
  EXPECT_EQ(a->points, b->points);
  EXPECT_EQ(a->point_attributes.at("label"), b->point_attributes.at("label"));
}

TEST(ScanSimulator, EveryRoomHasAStationAndPointsCarryLabels) {
  const Apartment apt = Generate(12);
  const auto stations = ScanStations(apt, Coarse());
  std::set<int> rooms_with_station;
  for (const auto& s : stations)
    for (const RoomGt& r : apt.rooms)
      if (s.x() > r.x0 && s.x() < r.x1 && s.y() > r.y0 && s.y() < r.y1) rooms_with_station.insert(r.id);
  EXPECT_EQ(rooms_with_station.size(), apt.rooms.size());
  Result<PointCloud> c = SimulateScan(apt, Coarse());
  ASSERT_TRUE(c.ok());
  const auto& label = c->point_attributes.at("label");
  ASSERT_EQ(label.size(), c->points.size());
  std::set<int> seen(label.begin(), label.end());
  EXPECT_TRUE(seen.count(nyu40::kWall) && seen.count(nyu40::kFloor) && seen.count(nyu40::kCeiling));
  EXPECT_FALSE(seen.count(0)) << "every simulated point hits a labelled face";
}

TEST(ScanSimulator, RangeNoiseAsConfigured) {
  const Apartment apt = Generate(13);
  ScanSimulationOptions exact = Coarse();
  exact.noise_sigma_m = 0;
  exact.noise_quadratic = 0;
  Result<PointCloud> c = SimulateScan(apt, exact);
  ASSERT_TRUE(c.ok());
  const auto& label = c->point_attributes.at("label");
  double worst = 0;
  for (size_t i = 0; i < label.size(); ++i)
    if (label[i] == nyu40::kFloor) worst = std::max(worst, std::fabs(c->points[i].z() - apt.floor_z_m));
  EXPECT_LT(worst, 1e-4) << "noise-free floor points lie on the floor";

  ScanSimulationOptions noisy = Coarse();
  noisy.noise_sigma_m = 0.01;
  noisy.noise_quadratic = 0;
  Result<PointCloud> n = SimulateScan(apt, noisy);
  ASSERT_TRUE(n.ok());
  double sum2 = 0;
  size_t count = 0;
  const auto& nl = n->point_attributes.at("label");
  for (size_t i = 0; i < nl.size(); ++i)
    if (nl[i] == nyu40::kCeiling) sum2 += std::pow(n->points[i].z() - apt.ceiling_z_m, 2), ++count;
  ASSERT_GT(count, 100u);
  // Ceiling seen from below at various angles: vertical spread a bit under the range sigma.
  const double rms = std::sqrt(sum2 / double(count));
  EXPECT_GT(rms, 0.004);
  EXPECT_LT(rms, 0.012);
}

}  // namespace
}  // namespace semvox
