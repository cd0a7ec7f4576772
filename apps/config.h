// The pipeline configuration (pipeline/pipeline_config.h) read from and written to one YAML file.
//
// The YAML file has one section per stage (input, mapping, occupancy, ...) holding that stage's option
// fields by name. Unknown sections or keys and out-of-range values are errors naming the key and the
// allowed range. The effective configuration is written beside the outputs (config_used.yaml).
#pragma once

#include <string>
#include <vector>

#include "core/option_table.h"
#include "core/status.h"
#include "pipeline/pipeline_config.h"

namespace semvox {

// One key of the YAML file: its section and the option, from the stage's options table (core/option_table.h).
struct ConfigKey {
  std::string section;
  Option<PipelineConfig> option;
};
// Every key, in the order of `semvox config --dump`.
const std::vector<ConfigKey>& ConfigKeys();

// Applies the settings in `path` on top of `config`.
Status LoadConfigFile(const std::string& path, PipelineConfig* config);
// Same, from YAML text (`name` appears in messages).
Status ParseConfig(const std::string& yaml_text, const std::string& name, PipelineConfig* config);
// Every option with its value and a comment giving units, range and meaning.
std::string DumpConfig(const PipelineConfig& config);

}  // namespace semvox
