// Sub-commands of the semvox binary. main.cc parses the command line (CLI11) and calls these.
#pragma once

#include <string>

#include "apps/config.h"
#include "core/status.h"

namespace semvox {

struct RunArgs {
  std::string input;
  std::string outdir;
  std::string config_path;     // Optional YAML file.
  std::string up;              // "", "auto", "z" or "y" (overrides the config when set).
  double scale = 0;            // > 0 overrides the config.
  bool json = false;           // Print summary.json on stdout.
};

// `semvox run`: load, voxelise, write map.bt, occupancy.{pgm,yaml}, summary.json, config_used.yaml.
Status RunPipeline(const RunArgs& args);

struct GenerateArgs {
  std::string outdir;
  bool demo = false;  // The bundled demo apartment instead of a random one.
  int seed = 0;
};

// `semvox generate`: writes a labelled apartment (mesh.ply, ...) into OUTDIR.
Status RunGenerate(const GenerateArgs& args);

}  // namespace semvox
