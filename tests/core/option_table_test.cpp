// OptionTable: one declaration per field gives Check(), ToJson(), Set/SetText and Apply with
// usage errors that name the field, its range and what was given.
#include "al/core/option_table.hpp"

#include <cstdint>
#include <limits>
#include <string>

#include <gtest/gtest.h>

namespace {

enum class Mode { kA, kB };

struct Example {
  int k = 10;
  std::size_t count = 3;
  double delta = 0.8;
  bool spatial = true;
  std::string label = "x";
  Mode mode = Mode::kA;

  static const al::OptionTable<Example>& Table() {
    static const auto table = al::OptionTable<Example>("example")
                                  .Int("k", &Example::k, al::NumericRange::Closed(1, 1000), "neighbours per node")
                                  .Int("count", &Example::count, al::NumericRange::AtLeast(0), "items")
                                  .Real("delta", &Example::delta, al::NumericRange::LeftOpen(0.0, 2.0), "gate")
                                  .Flag("spatial", &Example::spatial, "spatial factor")
                                  .Text("label", &Example::label, "a name")
                                  .Choice("mode", &Example::mode, {{"a", Mode::kA}, {"b", Mode::kB}}, "mode");
    return table;
  }
};

std::string UsageMessage(const std::function<void()>& f) {
  try {
    f();
  } catch (const al::Error& e) {
    EXPECT_EQ(e.code(), al::ExitCode::kUsage) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "no al::Error thrown";
  return "";
}

TEST(OptionTable, DefaultsPassAndSerialise) {
  const Example e;
  EXPECT_NO_THROW(Example::Table().Check(e));
  const nlohmann::json j = Example::Table().ToJson(e);
  EXPECT_EQ(j.dump(), R"({"count":3,"delta":0.8,"k":10,"label":"x","mode":"a","spatial":true})");
  ASSERT_EQ(Example::Table().fields().size(), 6u);
  EXPECT_EQ(Example::Table().fields()[0].name, "k");
  EXPECT_EQ(Example::Table().fields()[0].range, "[1, 1000]");
  EXPECT_EQ(Example::Table().fields()[1].range, ">= 0");
  EXPECT_EQ(al::NumericRange::Above(0).Text(), "> 0");
  EXPECT_EQ(al::NumericRange::Open(0, 2).Text(), "(0, 2)");
  EXPECT_EQ(al::NumericRange::Any().Text(), "finite numbers");
}

TEST(OptionTable, CheckNamesTheFieldItsRangeAndTheValue) {
  Example e;
  e.k = 0;
  EXPECT_EQ(UsageMessage([&] { Example::Table().Check(e); }),
            "example option 'k' = 0 must be in [1, 1000] (neighbours per node)");
  e = Example{};
  e.delta = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(UsageMessage([&] { Example::Table().Check(e); }).find("'delta'"), std::string::npos);
  e.delta = 2.5;
  EXPECT_NE(UsageMessage([&] { Example::Table().Check(e); }).find("(0, 2]"), std::string::npos);
  e.delta = 0.0;  // the open end
  EXPECT_NE(UsageMessage([&] { Example::Table().Check(e); }).find("'delta' = 0 must be in (0, 2]"), std::string::npos);
  e.delta = 2.0;
  EXPECT_NO_THROW(Example::Table().Check(e));
}

TEST(OptionTable, SetTextParsesEachType) {
  Example e;
  const auto& t = Example::Table();
  t.SetText(e, "k", " 12 ");
  t.SetText(e, "delta", "1e-1");
  t.SetText(e, "spatial", "off");
  t.SetText(e, "label", "room");
  t.SetText(e, "mode", "b");
  EXPECT_EQ(e.k, 12);
  EXPECT_DOUBLE_EQ(e.delta, 0.1);
  EXPECT_FALSE(e.spatial);
  EXPECT_EQ(e.label, "room");
  EXPECT_EQ(e.mode, Mode::kB);
}

TEST(OptionTable, BadTextAndJsonAreUsageErrors) {
  Example e;
  const auto& t = Example::Table();
  EXPECT_EQ(UsageMessage([&] { t.SetText(e, "k", "2.5"); }), "example option 'k' must be an integer, not '2.5'");
  EXPECT_EQ(UsageMessage([&] { t.SetText(e, "delta", "nan"); }), "example option 'delta': 'nan' is not a finite number");
  EXPECT_EQ(UsageMessage([&] { t.SetText(e, "spatial", "maybe"); }),
            "example option 'spatial': 'maybe' is not on|off|true|false|1|0");
  EXPECT_EQ(UsageMessage([&] { t.SetText(e, "mode", "c"); }), "example option 'mode' must be one of a|b, not 'c'");
  EXPECT_EQ(UsageMessage([&] { t.Set(e, "k", "10"); }), "example option 'k' must be an integer, not \"10\"");
  EXPECT_EQ(UsageMessage([&] { t.Set(e, "spatial", 1); }), "example option 'spatial' must be true or false, not 1");
  EXPECT_EQ(UsageMessage([&] { t.Set(e, "kk", 1); }),
            "example: unknown option 'kk' (known: k, count, delta, spatial, label, mode)");
  EXPECT_EQ(e.k, 10);  // nothing was stored by the failed calls
}

TEST(OptionTable, ApplyTakesAJsonObjectThenChecks) {
  Example e;
  Example::Table().Apply(e, {{"k", 4}, {"delta", 1.0}, {"mode", "b"}});
  EXPECT_EQ(e.k, 4);
  EXPECT_EQ(e.mode, Mode::kB);
  EXPECT_NE(UsageMessage([&] { Example::Table().Apply(e, {{"delta", 0.5}, {"k", -1}}); }).find("must be in [1, 1000]"),
            std::string::npos);
  EXPECT_EQ(e.k, 4);  // an invalid object changes nothing
  EXPECT_DOUBLE_EQ(e.delta, 1.0);
  EXPECT_EQ(UsageMessage([&] { Example::Table().Apply(e, nlohmann::json::array()); }),
            "example options must be a JSON object");
}

// A choice that names on|off takes JSON true/false as those names (Python's centre=False, a
// sweep grid of booleans); for any other choice a boolean is a named usage error.
TEST(OptionTable, ChoiceTakesABooleanAsOnOff) {
  enum class Tri { kAuto, kOn, kOff };
  struct Switches {
    Tri tri = Tri::kAuto;
  };
  const auto table = al::OptionTable<Switches>("switches").Choice(
      "tri", &Switches::tri, {{"auto", Tri::kAuto}, {"on", Tri::kOn}, {"off", Tri::kOff}}, "three ways");
  Switches s;
  table.Set(s, "tri", false);
  EXPECT_EQ(s.tri, Tri::kOff);
  table.Set(s, "tri", true);
  EXPECT_EQ(s.tri, Tri::kOn);
  Example e;
  EXPECT_EQ(UsageMessage([&] { Example::Table().Set(e, "mode", true); }),
            "example option 'mode' must be one of a|b, not 'on'");
}

TEST(OptionTable, FlagNamesUseDashes) {
  al::OptionField<Example> f;
  f.name = "min_segment_share";
  EXPECT_EQ(f.Flag(), "--min-segment-share");
}

}  // namespace
