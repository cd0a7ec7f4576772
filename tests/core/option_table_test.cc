#include "core/option_table.h"

#include <gtest/gtest.h>

#include <cmath>

namespace semvox {
namespace {

enum class Shape { kRound, kSquare };
bool ParseShape(const std::string& name, Shape* shape) {
  if (name == "round") *shape = Shape::kRound;
  else if (name == "square") *shape = Shape::kSquare;
  else return false;
  return true;
}

struct InnerOptions {
  int count = 3;
  static const OptionTable<InnerOptions>& Options() {
    static const OptionTable<InnerOptions> table = {
        OptionNumber(&InnerOptions::count, "count", 1, 10, "", "how many"),
    };
    return table;
  }
};

struct ToyOptions {
  double size_m = 0.5;
  Shape shape = Shape::kSquare;
  bool fast = true;
  InnerOptions inner;
  static const OptionTable<ToyOptions>& Options() {
    using O = ToyOptions;
    static const OptionTable<O> table = JoinOptions<O>({
        {
            OptionNumber(&O::size_m, "size_m", 0.01, 2, "metres", "edge"),
            OptionChoice(&O::shape, "shape", {"round", "square"}, ParseShape, "outline"),
            OptionSwitch(&O::fast, "fast", "skip the slow part"),
        },
        NestedOptions(&O::inner, InnerOptions::Options()),
    });
    return table;
  }
};

TEST(OptionTable, ReadsAndSetsEveryKindOfField) {
  ToyOptions t;
  const OptionTable<ToyOptions>& table = ToyOptions::Options();
  ASSERT_EQ(table.size(), 4u);
  EXPECT_EQ(OptionValueText(t, table[0]), "0.5");
  EXPECT_EQ(OptionValueText(t, table[1]), "square");
  EXPECT_EQ(OptionValueText(t, table[2]), "true");
  EXPECT_EQ(OptionValueText(t, table[3]), "3");
  table[0].set_number(t, 1.25);
  table[1].set_word(t, "round");
  table[2].set_word(t, "false");
  table[3].set_number(t, 7);
  EXPECT_EQ(t.size_m, 1.25);
  EXPECT_EQ(t.shape, Shape::kRound);
  EXPECT_FALSE(t.fast);
  EXPECT_EQ(t.inner.count, 7);
  EXPECT_TRUE(table[3].spec.integer);
  EXPECT_FALSE(table[0].spec.integer);
}

TEST(OptionTable, DescribesUnitAndRange) {
  const OptionTable<ToyOptions>& table = ToyOptions::Options();
  EXPECT_EQ(table[0].spec.Description(), "edge, metres");
  EXPECT_EQ(table[0].spec.Range(), "[0.01, 2]");
  EXPECT_EQ(table[1].spec.Description(), "outline");
  EXPECT_EQ(table[1].spec.Range(), "round | square");
  EXPECT_EQ(table[3].spec.Range(), "[1, 10]");
}

TEST(OptionTable, CheckNamesTheFieldItsValueAndTheRange) {
  ToyOptions t;
  std::string error;
  EXPECT_TRUE(CheckOptions(t, ToyOptions::Options(), &error)) << error;
  t.size_m = 0;
  EXPECT_FALSE(CheckOptions(t, ToyOptions::Options(), &error));
  EXPECT_EQ(error, "size_m = 0 is out of range [0.01, 2]");
  t.size_m = std::nan("");
  EXPECT_FALSE(CheckOptions(t, ToyOptions::Options(), &error));
  EXPECT_EQ(error, "size_m = nan is out of range [0.01, 2]");
  t = ToyOptions{};
  t.inner.count = 11;
  EXPECT_FALSE(CheckOptions(t, ToyOptions::Options(), &error));
  EXPECT_EQ(error, "count = 11 is out of range [1, 10]");
  t = ToyOptions{};
  t.shape = static_cast<Shape>(7);
  EXPECT_FALSE(CheckOptions(t, ToyOptions::Options(), &error));
  EXPECT_EQ(error, "shape is none of round | square");
}

}  // namespace
}  // namespace semvox
