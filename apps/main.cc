// The semvox command-line tool: one binary with sub-commands.
#include <CLI/CLI.hpp>

#include <csignal>
#include <cstdio>
#include <iostream>
#include <unistd.h>

#include "apps/commands.h"
#include "apps/config.h"
#include "core/file_util.h"
#include "core/log.h"

namespace {

void OnSignal(int sig) {
  semvox::RemovePendingTemporaries();
  const char msg[] = "semvox: interrupted; no partial outputs were left\n";
  ssize_t ignored = ::write(2, msg, sizeof(msg) - 1);
  (void)ignored;
  _exit(128 + sig);
}

int Report(const semvox::Status& st) {
  if (st.ok()) return 0;
  std::fprintf(stderr, "semvox: error: %s\n", st.message().c_str());
  return st.exit_code();
}

}  // namespace

int main(int argc, char** argv) {
  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);

  CLI::App app{"semvox: scanned apartment -> labelled 3D voxel map with rooms"};
  app.require_subcommand(1);
  bool quiet = false;
  app.add_flag("-q,--quiet", quiet, "print warnings and errors only");

  semvox::RunArgs run;
  CLI::App* run_cmd = app.add_subcommand("run", "map a mesh or point cloud into OUTDIR");
  run_cmd->add_option("input", run.input, "mesh (.ply .obj .gltf .glb .off .stl) or cloud (.ply .pcd .txt .xyz)")->required();
  run_cmd->add_option("-o,--output", run.outdir, "output directory")->required();
  run_cmd->add_option("--config", run.config_path, "YAML configuration (see `semvox config --dump`)");
  run_cmd->add_option("--up", run.up, "up axis of the input: auto, z or y")->check(CLI::IsMember({"auto", "z", "y"}));
  run_cmd->add_option("--scale", run.scale, "multiply coordinates into metres (0.001 for mm)")->check(CLI::PositiveNumber);
  run_cmd->add_flag("--json", run.json, "print summary.json on stdout");
  run_cmd->add_flag("-q,--quiet", quiet, "print warnings and errors only");

  semvox::GenerateArgs gen;
  CLI::App* gen_cmd = app.add_subcommand("generate", "write a labelled synthetic apartment into OUTDIR");
  gen_cmd->add_option("-o,--output", gen.outdir, "output directory")->required();
  gen_cmd->add_flag("--demo", gen.demo, "the bundled demo apartment");
  gen_cmd->add_option("--seed", gen.seed, "random seed");

  bool dump = false;
  std::string check_path;
  CLI::App* config_cmd = app.add_subcommand("config", "print or check the configuration");
  config_cmd->add_flag("--dump", dump, "print every option with its default, units and range");
  config_cmd->add_option("--check", check_path, "validate a YAML configuration file");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);
    std::fprintf(stderr, "semvox: error: %s (hint: semvox %s--help)\n", e.what(),
                 app.get_subcommands().empty() ? "" : (app.get_subcommands()[0]->get_name() + " ").c_str());
    return 2;
  }
  if (quiet) semvox::SetLogLevel(semvox::LogLevel::kWarning);

  try {
    if (*run_cmd) return Report(semvox::RunPipeline(run));
    if (*gen_cmd) return Report(semvox::RunGenerate(gen));
    if (*config_cmd) {
      semvox::PipelineConfig config;
      if (!check_path.empty()) {
        semvox::Status st = semvox::LoadConfigFile(check_path, &config);
        if (!st.ok()) return Report(st);
        std::printf("%s: ok\n", check_path.c_str());
      }
      if (dump || check_path.empty()) std::cout << semvox::DumpConfig(config);
      return 0;
    }
  } catch (const std::bad_alloc&) {
    semvox::RemovePendingTemporaries();
    return Report(semvox::Status::Internal("out of memory (hint: use larger voxels or raise the machine's memory)"));
  } catch (const std::exception& e) {
    semvox::RemovePendingTemporaries();
    return Report(semvox::Status::Internal(std::string("internal error: ") + e.what()));
  }
  return 0;
}
