#include "core/option_table.h"

#include <iomanip>
#include <sstream>

namespace semvox {

std::string FormatOptionNumber(double value, bool integer) {
  std::ostringstream os;
  if (integer) os << static_cast<long long>(value);
  else os << value;
  return os.str();
}

std::string OptionSpec::Description() const { return unit.empty() ? doc : doc + ", " + unit; }

std::string OptionSpec::Range() const {
  std::ostringstream os;
  if (!is_number()) {
    for (size_t i = 0; i < choices.size(); ++i) os << (i ? " | " : "") << choices[i];
  } else {
    os << "[" << FormatOptionNumber(min, integer) << ", " << FormatOptionNumber(max, integer) << "]";
  }
  return os.str();
}

std::string OptionSpec::NumberError(double value) const {
  if (Contains(value)) return "";
  std::ostringstream os;
  os << key << " = " << std::setprecision(12) << value << " is out of range " << Range();
  return os.str();
}

}  // namespace semvox
