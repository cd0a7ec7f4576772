// `semvox report OUTDIR`: (re)writes OUTDIR/report.html from the files a `semvox run` left there.
#include <filesystem>

#include "apps/commands.h"
#include "core/log.h"
#include "report/report.h"

namespace semvox {

Status RunReport(const ReportArgs& args) {
  ReportOptions options;
  SEMVOX_RETURN_IF_ERROR(WriteReport(args.outdir, options));
  SEMVOX_INFO("wrote " << (std::filesystem::path(args.outdir) / options.output_name).string());
  return Status::Ok();
}

}  // namespace semvox
