// report.html: one self-contained page per run, written from what `semvox run` left in OUTDIR.
//
//   ReportOptions options;                       // defaults suit every run
//   ReportSummary summary;
//   Status st = WriteReport(outdir, options, &summary);  // reads OUTDIR/summary.json, ...; writes OUTDIR/report.html
//
// Inputs (each optional except summary.json; an absent one shows "not computed", nothing is invented):
//   summary.json                    input statistics, voxel counts, seconds per stage, and when present the
//                                   semantic / voxel_crf sections (iterations with energies, label histogram),
//                                   the voxel size and the canonical frame (for the 3D view);
//   occupancy.pgm                   map_server top view (0 occupied, 254 free, 205 unknown);
//   semantic_topview.png            coloured semantic top view;
//   rooms.png + rooms.geojson       16-bit room ids (coloured here) and the room table (id, type, probability,
//                                   second type, area, ceiling height);
//   voxels.ply                      per-voxel NYU40 `label` (the class histogram, else summary's labels) and the
//                                   3D view's voxels (label, confidence, room, completed; src/report/view3d.h).
// The page has inline CSS, images as base64 PNG data URIs and, for the 3D view, inline scripts: three.js (read
// from `three_js_path` when the page is written) and the view's own; no external URL: it works offline.
// A malformed summary.json, top view or rooms.geojson is an error naming the file. A missing or damaged
// voxels.ply, or a missing three.js, never is: the 3D view is replaced by one line saying why (and the class
// histogram falls back to summary.json). The page is written atomically.
#pragma once

#include <string>

#include "core/geometry.h"
#include "core/option_table.h"
#include "core/status.h"

namespace semvox {

struct ReportOptions {
  std::string output_name = "report.html";  // File name inside OUTDIR (no directory part).
  int image_display_width_px = 640;         // Top views are shown at about this width (integer zoom, nearest pixel).
  bool read_voxels_ply = true;              // Class histogram from voxels.ply when present (else from summary.json).
  bool view_3d = true;
  int view_3d_max_voxels = 1000000;         // At the top about 180 MB of page.
  std::string three_js_path;                // three.js (UMD build, e.g. three.min.js) inlined for the 3D view; empty:
                                            // DefaultThreeJsPath().

  // The fields users set (section `report`): meaning, unit and range.
  static const OptionTable<ReportOptions>& Options() {
    using O = ReportOptions;
    static const OptionTable<O> table = {
        OptionSwitch(&O::view_3d, "view_3d",
                     "interactive 3D view of voxels.ply in report.html (three.js inlined; `semvox report --no-3d` leaves it out)"),
        OptionNumber(&O::view_3d_max_voxels, "view_3d_max_voxels", 1000, 10000000, "",
                     "voxels in the 3D view at most (about 18 bytes each in the page); larger maps merge 2x2x2 blocks "
                     "until they fit"),
    };
    return table;
  }
  bool Check(std::string* error) const;
};

// What WriteReport / RenderReportHtml wrote.
struct ReportSummary {
  bool view_3d = false;                     // The page holds the 3D view.
  std::string view_3d_absent;               // Why it does not (empty when it does or when options.view_3d is false).
  size_t view_3d_voxels = 0;                // Voxels in the view (after merging).
  int view_3d_merge = 1;                    // Map voxels per view voxel edge (1: none merged).
  size_t bytes = 0;                         // Size of the page.
};

// three.js for the 3D view: $SEMVOX_THREE_JS when set, else the file CMake found at configure time (Debian's
// libjs-three: /usr/share/javascript/three/three.min.js).
std::string DefaultThreeJsPath();

// Reads OUTDIR's outputs and writes OUTDIR/<options.output_name>; `summary` (optional) says what it holds.
Status WriteReport(const std::string& outdir, const ReportOptions& options = {}, ReportSummary* summary = nullptr);

// The page's HTML text (what WriteReport writes).
Result<std::string> RenderReportHtml(const std::string& outdir, const ReportOptions& options = {}, ReportSummary* summary = nullptr);

// Display colour of room `id` >= 1 in the report's room view and table: pastel hues spaced by the golden
// angle; every channel is at most 242, so no room colour equals the page's own background colours.
Rgb8 RoomDisplayColour(int id);

// Background of the room table's body rows (rgb(255, 243, 176)); tests look for it in screenshots.
inline constexpr Rgb8 kRoomTableBackground{255, 243, 176};
inline constexpr int kRoomTableRowHeightPx = 22;  // CSS height of one body row of the room table.

}  // namespace semvox
