#include "apps/config.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <sstream>
#include <vector>

#include "core/file_util.h"

namespace semvox {

const std::vector<ConfigKey>& ConfigKeys() {
  static const std::vector<ConfigKey> kKeys = [] {
    std::vector<ConfigKey> keys;
    const auto add = [&keys](const char* section, const OptionTable<PipelineConfig>& table) {
      for (const Option<PipelineConfig>& o : table) keys.push_back({section, o});
    };
    using C = PipelineConfig;
    add("input", NestedOptions(&C::load, LoadOptions::Options()));
    add("mapping", NestedOptions(&C::voxelize, VoxelizeOptions::Options()));
    add("occupancy", NestedOptions(&C::occupancy, OccupancyOptions::Options()));
    add("rooms", NestedOptions(&C::rooms, RoomSegmentationOptions::Options()));
    add("rooms", NestedOptions(&C::floor_plan, FloorPlanOptions::Options()));
    add("room_types", NestedOptions(&C::room_types, RoomTypeCrfOptions::Options()));
    add("render", NestedOptions(&C::render, ViewsOptions::Options()));
    add("semantic", NestedOptions(&C::semantic, SemanticStageOptions::Options()));
    add("objects", NestedOptions(&C::objects, SupportStageOptions::Options()));
    add("report", NestedOptions(&C::report, ReportOptions::Options()));
    return keys;
  }();
  return kKeys;
}

Status ParseConfig(const std::string& yaml_text, const std::string& name, PipelineConfig* config) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    return Status::InvalidInput(FileError(name, std::string("invalid YAML: ") + e.what(), "check indentation and colons"));
  }
  if (root.IsNull()) return Status::Ok();
  if (!root.IsMap())
    return Status::InvalidInput(FileError(name, "the configuration must be a map of sections", "see `semvox config --dump`"));
  for (const auto& sec : root) {
    const std::string section = sec.first.as<std::string>("");
    bool section_known = false;
    for (const ConfigKey& k : ConfigKeys()) section_known |= k.section == section;
    if (!section_known)
      return Status::InvalidInput(FileError(name, "unknown section '" + section + "'", "see `semvox config --dump`"));
    if (!sec.second.IsMap())
      return Status::InvalidInput(FileError(name, "section '" + section + "' must be a map of key: value", ""));
    for (const auto& kv : sec.second) {
      const std::string key = kv.first.as<std::string>("");
      const ConfigKey* field = nullptr;
      for (const ConfigKey& k : ConfigKeys())
        if (k.section == section && k.option.spec.key == key) field = &k;
      if (!field)
        return Status::InvalidInput(FileError(name, "unknown key '" + section + "." + key + "'", "see `semvox config --dump`"));
      const std::string full = section + "." + key;
      if (!kv.second.IsScalar())
        return Status::InvalidInput(FileError(name, full + " must be a single value", ""));
      const std::string text = kv.second.Scalar();
      const OptionSpec& spec = field->option.spec;
      if (!spec.is_number()) {
        bool ok = false;
        std::string all;
        for (const auto& c : spec.choices) ok |= c == text, all += (all.empty() ? "" : ", ") + c;
        if (!ok) return Status::InvalidInput(FileError(name, full + " = '" + text + "'. Allowed: " + all, ""));
        field->option.set_word(*config, text);
        continue;
      }
      char* end = nullptr;
      const double v = std::strtod(text.c_str(), &end);
      if (end == text.c_str() || *end != '\0' || !std::isfinite(v))
        return Status::InvalidInput(FileError(name, full + " = '" + text + "' is not a number", ""));
      if (spec.integer && v != std::floor(v))
        return Status::InvalidInput(FileError(name, full + " = " + text + " must be an integer", ""));
      if (!spec.Contains(v))
        return Status::InvalidInput(FileError(name, full + " = " + text + " is out of range " + spec.Range(), ""));
      field->option.set_number(*config, v);
    }
  }
  return CheckConfig(*config);
}

Status LoadConfigFile(const std::string& path, PipelineConfig* config) {
  std::string text;
  SEMVOX_RETURN_IF_ERROR(ReadFileBytes(path, &text));
  return ParseConfig(text, path, config);
}

std::string DumpConfig(const PipelineConfig& config) {
  std::ostringstream os;
  os << "# semvox configuration. Every key is optional; unknown keys are errors.\n";
  std::string section;
  for (const ConfigKey& k : ConfigKeys()) {
    if (k.section != section) {
      section = k.section;
      os << section << ":\n";
    }
    const OptionSpec& spec = k.option.spec;
    os << "  " << spec.key << ": " << OptionValueText(config, k.option) << "  # " << spec.Description() << "; "
       << spec.Range() << "\n";
  }
  return os.str();
}

}  // namespace semvox
