// `semvox labels`: the label vocabularies of core/labels.h as Markdown tables (docs/labels.md is made from it).
#include <cstdio>
#include <iostream>
#include <map>
#include <sstream>

#include "apps/commands.h"
#include "core/labels.h"

namespace semvox {

std::string LabelsMarkdown() {
  std::ostringstream os;
  const auto& labels = Nyu40Labels();
  auto hex = [](const Rgb8& c) {
    char buf[8];
    std::snprintf(buf, sizeof(buf), "#%02x%02x%02x", c.r, c.g, c.b);
    return std::string(buf);
  };
  os << "## NYU40 classes\n\n"
     << "| NYU40 id | name | Eigen-13 id | Eigen-13 name | NYU-4 id | NYU-4 name | display colour |\n"
     << "|---:|---|---:|---|---:|---|---|\n";
  for (const LabelInfo& l : labels)
    os << "| " << l.id << " | " << l.name << " | " << l.eigen13_id << " | " << l.eigen13_name << " | " << l.nyu4_id << " | "
       << l.nyu4_name << " | `" << hex(l.color) << "` |\n";
  // Super-classes with the NYU40 classes they gather.
  auto gather = [&](const char* title, auto id_of, auto name_of) {
    std::map<int, std::pair<std::string, std::string>> groups;  // id -> (name, NYU40 members)
    for (const LabelInfo& l : labels) {
      if (l.id == 0) continue;
      auto& g = groups[id_of(l)];
      g.first = name_of(l);
      g.second += (g.second.empty() ? "" : ", ") + std::to_string(l.id) + " " + l.name;
    }
    os << "\n## " << title << "\n\n| id | name | NYU40 classes |\n|---:|---|---|\n";
    for (const auto& [id, g] : groups) os << "| " << id << " | " << g.first << " | " << g.second << " |\n";
  };
  gather("Eigen-13 classes", [](const LabelInfo& l) { return l.eigen13_id; }, [](const LabelInfo& l) { return l.eigen13_name; });
  gather("NYU-4 classes", [](const LabelInfo& l) { return l.nyu4_id; }, [](const LabelInfo& l) { return l.nyu4_name; });
  os << "\n## Room types\n\n| id | name |\n|---:|---|\n";
  for (const RoomTypeInfo& r : RoomTypes()) os << "| " << r.id << " | " << r.name << " |\n";
  return os.str();
}

Status RunLabels() {
  std::cout << LabelsMarkdown();
  return Status::Ok();
}

}  // namespace semvox
