// An R2V plan (../shared/data/r2v) as the layout of a 3D apartment (library semvox_rooms_train, which
// joins the R2V reader of semvox_rooms with the generator's PlanLayout):
//
//   int unclosed = 0;
//   Result<PlanLayout> layout = LayoutOfR2vPlan("plan_0001.txt", &unclosed);
//   Result<Apartment> apartment = ApartmentFromLayout(*layout, PlanApartmentOptions{});
#pragma once

#include <string>

#include "core/status.h"
#include "scenegen/plan_apartment.h"

namespace semvox {

// The plan in metres (scale from its doors): walls, doors, the fixtures that are objects (toilet, bathtub,
// basin, cooking counter) and the room raster. Room labels in regions open to the plan's border are counted
// in `unclosed` (the rasteriser leaves those regions out). Fails with the file's name on a plan that cannot
// be read or rasterised.
Result<PlanLayout> LayoutOfR2vPlan(const std::string& path, int* unclosed);

}  // namespace semvox
