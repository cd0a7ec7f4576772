#include "rooms/room_export.h"

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "core/file_util.h"
#include "core/labels.h"

namespace semvox {
namespace {

// World coordinates of the centre of pixel (x, y); row 0 is the largest y.
Eigen::Vector2d PixelCentre(const FloorPlan& plan, double x, double y) {
  return {plan.origin_x + (x + 0.5) * plan.resolution_m, plan.origin_y + (plan.height() - y - 0.5) * plan.resolution_m};
}

double SignedArea(const std::vector<Eigen::Vector2d>& ring) {
  double a = 0;
  for (size_t i = 0, n = ring.size(); i < n; ++i) {
    const auto& p = ring[i];
    const auto& q = ring[(i + 1) % n];
    a += p.x() * q.y() - q.x() * p.y();
  }
  return 0.5 * a;
}

std::vector<Eigen::Vector2d> ToWorld(const FloorPlan& plan, const std::vector<cv::Point>& contour, bool ccw) {
  std::vector<Eigen::Vector2d> ring;
  ring.reserve(contour.size());
  for (const cv::Point& p : contour) ring.push_back(PixelCentre(plan, p.x, p.y));
  if ((SignedArea(ring) > 0) != ccw) std::reverse(ring.begin(), ring.end());
  return ring;
}

// A distinct, light colour per room id (golden-angle hues).
std::string RoomColour(int id) {
  const double h = std::fmod(id * 137.508, 360.0), s = 0.45, v = 0.95;
  const double c = v * s, x = c * (1 - std::fabs(std::fmod(h / 60.0, 2.0) - 1)), m = v - c;
  double r = 0, g = 0, b = 0;
  if (h < 60) r = c, g = x;
  else if (h < 120) r = x, g = c;
  else if (h < 180) g = c, b = x;
  else if (h < 240) g = x, b = c;
  else if (h < 300) r = x, b = c;
  else r = c, b = x;
  char buf[8];
  std::snprintf(buf, sizeof(buf), "#%02x%02x%02x", int((r + m) * 255), int((g + m) * 255), int((b + m) * 255));
  return buf;
}

std::string TypeName(int type_id) {
  const auto& types = RoomTypes();
  return type_id >= 0 && type_id < int(types.size()) ? types[type_id].name : "unknown";
}

// SVG path of the contours of `mask` in pixel coordinates (even-odd fill for holes).
std::string MaskPath(const cv::Mat1b& mask) {
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(mask.clone(), contours, cv::RETR_CCOMP, cv::CHAIN_APPROX_SIMPLE);
  std::ostringstream os;
  for (const auto& c : contours) {
    if (c.empty()) continue;
    os << "M" << c[0].x + 0.5 << " " << c[0].y + 0.5;
    for (size_t i = 1; i < c.size(); ++i) os << "L" << c[i].x + 0.5 << " " << c[i].y + 0.5;
    os << "Z";
  }
  return os.str();
}

}  // namespace

std::vector<RoomDescription> DescribeRooms(const FloorPlan& plan, const RoomSegmentation& rooms) {
  const int W = plan.width(), H = plan.height(), n = rooms.num_rooms;
  std::vector<RoomDescription> out(n);
  if (n == 0) return out;
  const double cell_area = plan.resolution_m * plan.resolution_m;
  std::vector<std::vector<float>> ceilings(n + 1);
  std::vector<int> x0(n + 1, W), y0(n + 1, H), x1(n + 1, -1), y1(n + 1, -1);
  std::vector<int64_t> cells(n + 1, 0);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const int id = rooms.room_extent_ids.at(x, y);
      if (id < 1 || id > n) continue;
      ++cells[id];
      x0[id] = std::min(x0[id], x), x1[id] = std::max(x1[id], x), y0[id] = std::min(y0[id], y), y1[id] = std::max(y1[id], y);
      const float c = plan.ceiling_height_m.at(x, y);
      if (c > 0 && rooms.room_ids.at(x, y) == id) ceilings[id].push_back(c);
    }
  for (int id = 1; id <= n; ++id) {
    RoomDescription& d = out[id - 1];
    d.id = id;
    d.area_m2 = double(cells[id]) * cell_area;
    if (!ceilings[id].empty()) {
      auto mid = ceilings[id].begin() + ceilings[id].size() / 2;
      std::nth_element(ceilings[id].begin(), mid, ceilings[id].end());
      d.ceiling_height_m = *mid;
    }
    if (x1[id] < 0) continue;
    // The room's mask with one pixel of margin, for contours and the deepest point.
    const cv::Rect roi(x0[id] - 1, y0[id] - 1, x1[id] - x0[id] + 3, y1[id] - y0[id] + 3);
    cv::Mat1b mask(roi.height, roi.width, uchar(0));
    for (int y = y0[id]; y <= y1[id]; ++y)
      for (int x = x0[id]; x <= x1[id]; ++x)
        if (rooms.room_extent_ids.at(x, y) == id) mask(y - roi.y, x - roi.x) = 255;
    cv::Mat1f dist;
    cv::distanceTransform(mask, dist, cv::DIST_L2, cv::DIST_MASK_5);
    cv::Point deepest;
    cv::minMaxLoc(dist, nullptr, nullptr, nullptr, &deepest);
    d.label_point = PixelCentre(plan, deepest.x + roi.x, deepest.y + roi.y);
    std::vector<std::vector<cv::Point>> contours;
    std::vector<cv::Vec4i> hierarchy;
    cv::findContours(mask, contours, hierarchy, cv::RETR_CCOMP, cv::CHAIN_APPROX_SIMPLE, cv::Point(roi.x, roi.y));
    for (size_t i = 0; i < contours.size(); ++i) {
      if (hierarchy[i][3] >= 0) continue;  // Holes are collected with their outer ring.
      std::vector<cv::Point> simple;
      cv::approxPolyDP(contours[i], simple, 0.7, true);
      if (simple.size() < 3) simple = contours[i];
      RoomPolygon poly;
      poly.outer = ToWorld(plan, simple, true);
      for (int h = hierarchy[i][2]; h >= 0; h = hierarchy[h][0]) {
        std::vector<cv::Point> hole;
        cv::approxPolyDP(contours[h], hole, 0.7, true);
        if (hole.size() >= 3) poly.holes.push_back(ToWorld(plan, hole, false));
      }
      d.polygons.push_back(std::move(poly));
    }
  }
  return out;
}

std::string RoomsToGeoJson(const std::vector<RoomDescription>& rooms, const Eigen::Isometry3d& input_from_world) {
  using nlohmann::ordered_json;
  const bool identity = IsIdentity(input_from_world);
  auto ring_json = [&](const std::vector<Eigen::Vector2d>& ring) {
    ordered_json r = ordered_json::array();
    for (const auto& q : ring) {
      const Eigen::Vector2d p = identity ? q : Eigen::Vector2d((input_from_world * Eigen::Vector3d(q.x(), q.y(), 0.0)).head<2>());
      r.push_back({std::round(p.x() * 1e4) / 1e4, std::round(p.y() * 1e4) / 1e4});
    }
    if (!ring.empty()) r.push_back(r.front());  // GeoJSON rings are closed.
    return r;
  };
  auto polygon_json = [&](const RoomPolygon& poly) {
    ordered_json rings = ordered_json::array();
    rings.push_back(ring_json(poly.outer));
    for (const auto& h : poly.holes) rings.push_back(ring_json(h));
    return rings;
  };
  ordered_json fc;
  fc["type"] = "FeatureCollection";
  fc["features"] = ordered_json::array();
  for (const RoomDescription& d : rooms) {
    ordered_json f;
    f["type"] = "Feature";
    f["id"] = d.id;
    ordered_json g;
    if (d.polygons.size() == 1) {
      g["type"] = "Polygon";
      g["coordinates"] = polygon_json(d.polygons[0]);
    } else {
      g["type"] = "MultiPolygon";
      g["coordinates"] = ordered_json::array();
      for (const auto& p : d.polygons) g["coordinates"].push_back(polygon_json(p));
    }
    f["geometry"] = g;
    ordered_json props;
    props["id"] = d.id;
    props["type"] = TypeName(d.type_id);
    props["type_id"] = d.type_id;
    props["type_probabilities"] = ordered_json::object();
    for (size_t t = 0; t < d.type_probabilities.size(); ++t) props["type_probabilities"][TypeName(int(t))] = d.type_probabilities[t];
    if (d.type_id > 0) {
      props["probability"] = std::round(d.type_probability * 1e4) / 1e4;
      props["second_type"] = TypeName(d.second_type_id);
      props["second_type_id"] = d.second_type_id;
      props["second_probability"] = std::round(d.second_type_probability * 1e4) / 1e4;
    }
    props["area_m2"] = std::round(d.area_m2 * 1e4) / 1e4;
    if (d.ceiling_height_m > 0) props["ceiling_height_m"] = std::round(d.ceiling_height_m * 1e3) / 1e3;
    else props["ceiling_height_m"] = nullptr;
    f["properties"] = props;
    fc["features"].push_back(f);
  }
  return fc.dump(1) + "\n";
}

std::string RoomsToSvg(const FloorPlan& plan, const RoomSegmentation& rooms, const std::vector<RoomDescription>& described) {
  const int W = plan.width(), H = plan.height();
  const double scale = std::clamp(1000.0 / std::max(1, std::max(W, H)), 1.0, 8.0);
  const int legend_w = 260, legend_line = 18;
  const int legend_h = 30 + legend_line * int(described.size());
  std::ostringstream os;
  os << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
     << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << int(W * scale) + legend_w << "\" height=\""
     << std::max(int(H * scale), legend_h) << "\">\n"
     << "<title>semvox rooms (" << described.size() << " rooms, " << plan.resolution_m << " m per cell)</title>\n"
     << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
     << "<g transform=\"scale(" << scale << ")\">\n";
  cv::Mat1b walls(H, W, uchar(0)), clutter(H, W, uchar(0));
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      walls(y, x) = plan.at(x, y) == FloorCell::kWall ? 255 : 0;
      clutter(y, x) = plan.at(x, y) == FloorCell::kClutter ? 255 : 0;
    }
  for (const RoomDescription& d : described) {
    cv::Mat1b mask(H, W, uchar(0));
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) mask(y, x) = rooms.room_extent_ids.at(x, y) == d.id ? 255 : 0;
    os << "<path fill-rule=\"evenodd\" fill=\"" << RoomColour(d.id) << "\" stroke=\"none\" d=\"" << MaskPath(mask)
       << "\"><title>room " << d.id << "</title></path>\n";
  }
  os << "<path fill-rule=\"evenodd\" fill=\"#888888\" fill-opacity=\"0.5\" d=\"" << MaskPath(clutter) << "\"/>\n";
  os << "<path fill-rule=\"evenodd\" fill=\"#202020\" d=\"" << MaskPath(walls) << "\"/>\n";
  os << "</g>\n";
  const double font = 12;
  for (const RoomDescription& d : described) {
    const double px = (d.label_point.x() - plan.origin_x) / plan.resolution_m * scale;
    const double py = (H - (d.label_point.y() - plan.origin_y) / plan.resolution_m) * scale;
    os << "<text x=\"" << px << "\" y=\"" << py << "\" font-family=\"sans-serif\" font-size=\"" << font
       << "\" text-anchor=\"middle\">" << d.id << " " << TypeName(d.type_id) << "</text>\n";
  }
  const int lx = int(W * scale) + 10;
  os << "<text x=\"" << lx << "\" y=\"20\" font-family=\"sans-serif\" font-size=\"14\" font-weight=\"bold\">Rooms</text>\n";
  for (size_t i = 0; i < described.size(); ++i) {
    const RoomDescription& d = described[i];
    const int y = 30 + legend_line * int(i);
    char area[32];
    std::snprintf(area, sizeof(area), "%.1f", d.area_m2);
    os << "<rect x=\"" << lx << "\" y=\"" << y << "\" width=\"14\" height=\"14\" fill=\"" << RoomColour(d.id)
       << "\" stroke=\"#404040\"/>"
       << "<text x=\"" << lx + 20 << "\" y=\"" << y + 12 << "\" font-family=\"sans-serif\" font-size=\"12\">" << d.id
       << ": " << TypeName(d.type_id) << ", " << area << " m²</text>\n";
  }
  os << "</svg>\n";
  return os.str();
}

Status WriteRoomIdsPng(const std::string& path, const ImageU16& ids) {
  cv::Mat m(ids.height, ids.width, CV_16UC1, const_cast<uint16_t*>(ids.data.data()));
  std::vector<uchar> buf;
  try {
    if (!cv::imencode(".png", m, buf)) return Status::Internal(FileError(path, "cannot encode the 16-bit PNG", ""));
  } catch (const cv::Exception& e) {
    return Status::Internal(FileError(path, std::string("cannot encode the 16-bit PNG: ") + e.what(), ""));
  }
  return WriteFileAtomic(path, std::string(buf.begin(), buf.end()));
}

Status WriteRoomOutputs(const std::string& dir, const FloorPlan& plan, const RoomSegmentation& rooms, bool png_only,
                        const Eigen::Isometry3d& input_from_world) {
  const std::filesystem::path base(dir);
  SEMVOX_RETURN_IF_ERROR(WriteRoomIdsPng((base / "rooms.png").string(), rooms.room_extent_ids));
  if (png_only) return Status::Ok();
  const std::vector<RoomDescription> described = DescribeRooms(plan, rooms);
  SEMVOX_RETURN_IF_ERROR(WriteFileAtomic((base / "rooms.geojson").string(), RoomsToGeoJson(described, input_from_world)));
  return WriteFileAtomic((base / "rooms.svg").string(), RoomsToSvg(plan, rooms, described));
}

Status WriteRoomOutputs(const std::string& dir, const FloorPlan& plan, const RoomSegmentation& rooms,
                        const std::vector<RoomDescription>& described, const Eigen::Isometry3d& input_from_world) {
  const std::filesystem::path base(dir);
  SEMVOX_RETURN_IF_ERROR(WriteRoomIdsPng((base / "rooms.png").string(), rooms.room_extent_ids));
  SEMVOX_RETURN_IF_ERROR(WriteFileAtomic((base / "rooms.geojson").string(), RoomsToGeoJson(described, input_from_world)));
  return WriteFileAtomic((base / "rooms.svg").string(), RoomsToSvg(plan, rooms, described));
}

}  // namespace semvox
