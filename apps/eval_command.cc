#include <cstdio>
#include <filesystem>

#include "apps/commands.h"
#include "core/file_util.h"
#include "core/log.h"
#include "eval/evaluate.h"
#include "io/image_io.h"

namespace semvox {

Status RunEval(const EvalArgs& args) {
  Result<EvalReport> report = Evaluate(args.pred_dir, args.gt_dir);
  if (!report.ok()) return report.status();
  const std::string out = args.output.empty() ? (std::filesystem::path(args.pred_dir) / "eval.json").string() : args.output;
  SEMVOX_RETURN_IF_ERROR(WriteFileAtomic(out, report->ToJson()));
  if (!report->top_view.geometric_diff.empty()) {
    const std::string diff = (std::filesystem::path(out).parent_path() / "eval_topview.png").string();
    SEMVOX_RETURN_IF_ERROR(WriteImage(diff, report->top_view.geometric_diff));
  }
  std::fputs(report->Table().c_str(), stdout);
  SEMVOX_INFO("wrote " << out);
  return Status::Ok();
}

}  // namespace semvox
