// One description per option: key, meaning, unit and allowed values, written once beside the field.
//
// An options struct that users configure lists the fields they may set in a static `Options()` table:
//
//   struct VoxelizeOptions {
//     double voxel_size_m = 0.05;
//     ...
//     static const OptionTable<VoxelizeOptions>& Options() {
//       static const OptionTable<VoxelizeOptions> table = {
//           OptionNumber(&VoxelizeOptions::voxel_size_m, "voxel_size_m", 0.005, 1.0, "metres", "voxel edge"),
//           ...};
//       return table;
//     }
//     bool Check(std::string* error) const;  // CheckOptions(*this, Options(), error) + cross-field rules.
//   };
//
// From that one table come the range check of `Check()` (the message names the field, its value and the
// range: "voxel_size_m = 0 is out of range [0.005, 1]"), the YAML reader and `semvox config --dump`
// (apps/config.cc), and docs/configuration.md (scripts/gen_docs.sh). Defaults are the struct's member
// initialisers. Fields that users cannot set keep their comment and a hand-written check.
#pragma once

#include <functional>
#include <initializer_list>
#include <string>
#include <type_traits>
#include <vector>

namespace semvox {

// What users are told about one option.
struct OptionSpec {
  std::string key;                   // The YAML key (the field's name, as a rule).
  std::string doc;                   // Meaning, one line, lower case, without the unit.
  std::string unit;                  // "metres", "degrees", "pixels", "m2", ...; empty when it has none.
  double min = 0, max = 0;           // Numbers: the inclusive range.
  bool integer = false;              // Numbers: whole numbers only.
  std::vector<std::string> choices;  // Words (enums, true / false): the allowed values; empty for numbers.

  bool is_number() const { return choices.empty(); }
  bool Contains(double value) const { return value >= min && value <= max; }  // False for NaN.
  // The meaning followed by the unit: "voxel edge, metres".
  std::string Description() const;
  // "[0.005, 1]" for numbers, "auto | z | y" for words.
  std::string Range() const;
  // "key = 0 is out of range [0.005, 1]" for a number outside the range (NaN included), empty when inside.
  std::string NumberError(double value) const;
};

// A number as the configuration prints it: integers without a fraction, others with 6 significant digits.
std::string FormatOptionNumber(double value, bool integer);

// One option of the options struct T: its spec and how to read and set it. Numbers go through double;
// words (enums, booleans) through their text.
template <class T>
struct Option {
  OptionSpec spec;
  std::function<double(const T&)> get_number;
  std::function<void(T&, double)> set_number;
  std::function<std::string(const T&)> get_word;  // Empty when the value is none of spec.choices.
  std::function<void(T&, const std::string&)> set_word;  // `word` is one of spec.choices.
};

template <class T>
using OptionTable = std::vector<Option<T>>;

// A number field (floating point, integer, or a bool read as 0 / 1) in [min, max].
template <class T, class M>
Option<T> OptionNumber(M T::*member, std::string key, double min, double max, std::string unit, std::string doc) {
  static_assert(std::is_arithmetic_v<M>, "OptionNumber: the field must be a number");
  Option<T> o;
  o.spec.key = std::move(key);
  o.spec.doc = std::move(doc);
  o.spec.unit = std::move(unit);
  o.spec.min = min;
  o.spec.max = max;
  o.spec.integer = std::is_integral_v<M>;
  o.get_number = [member](const T& t) { return double(t.*member); };
  o.set_number = [member](T& t, double v) { t.*member = static_cast<M>(v); };
  return o;
}

// A true / false field, written as the words.
template <class T>
Option<T> OptionSwitch(bool T::*member, std::string key, std::string doc) {
  Option<T> o;
  o.spec.key = std::move(key);
  o.spec.doc = std::move(doc);
  o.spec.choices = {"true", "false"};
  o.get_word = [member](const T& t) { return std::string(t.*member ? "true" : "false"); };
  o.set_word = [member](T& t, const std::string& w) { t.*member = w == "true"; };
  return o;
}

// An enum field written as one of `words`, each of which `parse` turns into its value.
template <class T, class E>
Option<T> OptionChoice(E T::*member, std::string key, std::vector<std::string> words,
                       bool (*parse)(const std::string&, E*), std::string doc) {
  Option<T> o;
  o.spec.key = std::move(key);
  o.spec.doc = std::move(doc);
  o.spec.choices = std::move(words);
  o.get_word = [member, parse, choices = o.spec.choices](const T& t) {
    for (const std::string& w : choices) {
      E e{};
      if (parse(w, &e) && e == t.*member) return w;
    }
    return std::string();
  };
  o.set_word = [member, parse](T& t, const std::string& w) { parse(w, &(t.*member)); };
  return o;
}

// The options of the nested struct `member` as options of its owner T (same keys and specs).
template <class T, class Sub>
OptionTable<T> NestedOptions(Sub T::*member, const OptionTable<Sub>& sub) {
  OptionTable<T> out;
  for (const Option<Sub>& s : sub) {
    Option<T> o;
    o.spec = s.spec;
    if (s.get_number) o.get_number = [member, f = s.get_number](const T& t) { return f(t.*member); };
    if (s.set_number) o.set_number = [member, f = s.set_number](T& t, double v) { f(t.*member, v); };
    if (s.get_word) o.get_word = [member, f = s.get_word](const T& t) { return f(t.*member); };
    if (s.set_word) o.set_word = [member, f = s.set_word](T& t, const std::string& w) { f(t.*member, w); };
    out.push_back(std::move(o));
  }
  return out;
}

// Tables one after the other, for a struct whose table interleaves its own fields with nested ones.
template <class T>
OptionTable<T> JoinOptions(std::initializer_list<OptionTable<T>> parts) {
  OptionTable<T> out;
  for (const OptionTable<T>& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

// The value of `option` in `t` as the configuration writes it ("0.05", "16", "true", "auto").
template <class T>
std::string OptionValueText(const T& t, const Option<T>& option) {
  if (!option.spec.is_number()) return option.get_word(t);
  return FormatOptionNumber(option.get_number(t), option.spec.integer);
}

// The range check of Check(): false with a message naming the first field of `table` whose value in
// `options` is outside its range (or none of its words).
template <class T>
bool CheckOptions(const T& options, const OptionTable<T>& table, std::string* error) {
  for (const Option<T>& o : table) {
    std::string message;
    if (o.spec.is_number()) message = o.spec.NumberError(o.get_number(options));
    else if (o.get_word(options).empty()) message = o.spec.key + " is none of " + o.spec.Range();
    if (message.empty()) continue;
    if (error) *error = message;
    return false;
  }
  return true;
}

}  // namespace semvox
