// report.html: one self-contained page per run, written from what `semvox run` left in OUTDIR.
//
//   ReportOptions options;                       // defaults suit every run
//   Status st = WriteReport(outdir, options);    // reads OUTDIR/summary.json, ...; writes OUTDIR/report.html
//
// Inputs (each optional except summary.json; an absent one shows "not computed", nothing is invented):
//   summary.json                    input statistics, voxel counts, seconds per stage, and when present the
//                                   semantic / voxel_crf sections (iterations with energies, label histogram);
//   occupancy.pgm                   map_server top view (0 occupied, 254 free, 205 unknown);
//   semantic_topview.png            coloured semantic top view;
//   rooms.png + rooms.geojson       16-bit room ids (coloured here) and the room table (id, type, probability,
//                                   second type, area, ceiling height);
//   voxels.ply                      per-voxel NYU40 `label` property: the class histogram (else summary's labels).
// The page has inline CSS and images as base64 PNG data URIs, no scripts and no external URL: it works offline.
// A malformed input file is an error naming the file; the page is written atomically.
#pragma once

#include <string>

#include "core/geometry.h"
#include "core/status.h"

namespace semvox {

struct ReportOptions {
  std::string output_name = "report.html";  // File name inside OUTDIR (no directory part).
  int image_display_width_px = 640;         // Top views are shown at about this width (integer zoom, nearest pixel).
  bool read_voxels_ply = true;              // Class histogram from voxels.ply when present (else from summary.json).
  bool Check(std::string* error) const;
};

// Reads OUTDIR's outputs and writes OUTDIR/<options.output_name>.
Status WriteReport(const std::string& outdir, const ReportOptions& options = {});

// The page's HTML text (what WriteReport writes).
Result<std::string> RenderReportHtml(const std::string& outdir, const ReportOptions& options = {});

// Display colour of room `id` >= 1 in the report's room view and table: pastel hues spaced by the golden
// angle; every channel is at most 242, so no room colour equals the page's own background colours.
Rgb8 RoomDisplayColour(int id);

// Background of the room table's body rows (rgb(255, 243, 176)); tests look for it in screenshots.
inline constexpr Rgb8 kRoomTableBackground{255, 243, 176};
inline constexpr int kRoomTableRowHeightPx = 22;  // CSS height of one body row of the room table.

}  // namespace semvox
