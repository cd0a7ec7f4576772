#include <cstdio>
#include <filesystem>

#include "apps/commands.h"
#include "core/file_util.h"
#include "core/log.h"
#include "eval/box_eval.h"
#include "eval/evaluate.h"
#include "eval/point_eval.h"
#include "io/image_io.h"

namespace semvox {

namespace {

// --boxes or --points: a real scan's furniture boxes or labelled points. Writes the JSON report only when -o is
// given (the run's directory stays as `semvox run` left it).
template <typename Report>
Status RunRealScanEval(const EvalArgs& args, Result<Report> report) {
  if (!report.ok()) return report.status();
  const std::string json = report->ToJson();
  if (!args.output.empty()) SEMVOX_RETURN_IF_ERROR(WriteFileAtomic(args.output, json));
  std::fputs(args.json ? json.c_str() : report->Table().c_str(), stdout);
  if (!args.output.empty()) SEMVOX_INFO("wrote " << args.output);
  return Status::Ok();
}

}  // namespace

Status RunEval(const EvalArgs& args) {
  if (!args.boxes_path.empty()) return RunRealScanEval(args, EvaluateRunAgainstBoxes(args.pred_dir, args.boxes_path));
  if (!args.points_path.empty()) return RunRealScanEval(args, EvaluateRunAgainstPoints(args.pred_dir, args.points_path));
  if (args.gt_dir.empty())
    return Status::InvalidInput("eval: no ground truth (hint: pass --gt DIR of `semvox generate`, or --boxes GT.json or --points "
                                "LABELLED.ply of a real scan)");
  Result<EvalReport> report = Evaluate(args.pred_dir, args.gt_dir);
  if (!report.ok()) return report.status();
  const std::string out = args.output.empty() ? (std::filesystem::path(args.pred_dir) / "eval.json").string() : args.output;
  const std::string json = report->ToJson();
  SEMVOX_RETURN_IF_ERROR(WriteFileAtomic(out, json));
  if (!report->top_view.geometric_diff.empty()) {
    const std::string diff = (std::filesystem::path(out).parent_path() / "eval_topview.png").string();
    SEMVOX_RETURN_IF_ERROR(WriteImage(diff, report->top_view.geometric_diff));
  }
  std::fputs(args.json ? json.c_str() : report->Table().c_str(), stdout);
  SEMVOX_INFO("wrote " << out);
  return Status::Ok();
}

}  // namespace semvox
