// One table per options struct: every user-settable field is declared once, with its name, range
// and help, and everything else is generated from that table — Check(), the CLI flags (src/cli),
// the report's `params`, the sweep grid axes and the solver-options JSON. A field added to a struct
// without a table row is invisible to users, so the table is where an option is born.
//
//   const OptionTable<GraphOptions>& GraphOptions::Table() {
//     static const auto table = OptionTable<GraphOptions>("graph")
//         .Int("k", &GraphOptions::k, 1, 1000, "neighbours per node")
//         .Real("delta", &GraphOptions::delta, 0.0, 2.0, "semantic gate (distance of unit features)");
//     return table;
//   }
#pragma once
#include <cmath>
#include <functional>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "al/core/error.hpp"

namespace al {

// How a value is spelled: on the command line, in a sweep grid, in JSON.
enum class OptionType { kInt, kReal, kFlag, kText, kChoice };

template <class O>
struct OptionField {
  std::string name;   // snake_case key of params / solver options / grid; CLI flag --name-with-dashes
  OptionType type = OptionType::kText;
  std::string range;  // "[1, 1000]", "distance|cosine"; empty: any value of the type
  std::string help;
  bool presence = false;  // a switch: the CLI flag takes no value and sets true (e.g. --restore)
  std::function<nlohmann::json(const O&)> get;
  // Stores a value already converted to the field's type (see OptionTable::Set); may throw a
  // usage error for values the type allows but the field cannot take (e.g. an unknown choice).
  std::function<void(O&, const nlohmann::json&)> set;
  std::function<bool(const O&)> in_range;

  std::string Flag() const {
    std::string flag = "--" + name;
    for (char& c : flag)
      if (c == '_') c = '-';
    return flag;
  }
};

std::string FormatOptionNumber(double value);                          // shortest round-trip text
// A field's value as the CLI spells it: "0.8", "on"/"off" for a boolean, "distance"; what --help,
// Python's docstrings and the range errors show.
std::string SpellOptionValue(const nlohmann::json& value);
nlohmann::json ParseOptionText(OptionType type, const std::string& text, const std::string& what);
nlohmann::json ConvertOptionJson(OptionType type, const nlohmann::json& value, const std::string& what);

// An interval of finite numbers, closed unless said otherwise: Closed(1, 1000), AtLeast(0),
// Above(0) (0 excluded), LeftOpen(0, 1) = (0, 1].
struct NumericRange {
  double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
  bool lo_open = false, hi_open = false;

  static NumericRange Closed(double lo, double hi) { return {lo, hi, false, false}; }
  static NumericRange LeftOpen(double lo, double hi) { return {lo, hi, true, false}; }
  static NumericRange Open(double lo, double hi) { return {lo, hi, true, true}; }
  static NumericRange AtLeast(double lo) { return {lo, std::numeric_limits<double>::infinity(), false, true}; }
  static NumericRange Above(double lo) { return {lo, std::numeric_limits<double>::infinity(), true, true}; }
  static NumericRange Any() { return {}; }

  bool Contains(double v) const {
    return std::isfinite(v) && (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
  }
  std::string Text() const;  // "[1, 1000]", "(0, 1]", ">= 0", "> 0", "finite numbers"
};

// Check() of an options struct without a table, in the tables' words: throws Error(kUsage)
// "SCOPE option 'NAME' = V must be in [lo, hi] (HELP)" when value is outside range (NaN always is).
void CheckOptionRange(const std::string& scope, const std::string& name, double value, const NumericRange& range,
                      const std::string& help);
// The usage error both checks throw: "SCOPE option 'NAME' = VALUE must be [in ]RANGE (HELP)".
Error OptionOutOfRange(const std::string& scope, const std::string& name, const std::string& value,
                       const std::string& range, const std::string& help);

template <class O>
class OptionTable {
 public:
  explicit OptionTable(std::string scope) : scope_(std::move(scope)) {}

  const std::string& scope() const { return scope_; }
  const std::vector<OptionField<O>>& fields() const { return fields_; }

  template <class I>
  OptionTable&& Int(const std::string& name, I O::*member, NumericRange range, const std::string& help) && {
    OptionField<O> f{name, OptionType::kInt, range.Text(), help, false, {}, {}, {}};
    f.get = [member](const O& o) { return nlohmann::json(o.*member); };
    f.set = [member](O& o, const nlohmann::json& v) { o.*member = static_cast<I>(v.get<double>()); };
    f.in_range = [member, range](const O& o) { return range.Contains(static_cast<double>(o.*member)); };
    return Add(std::move(f));
  }
  OptionTable&& Real(const std::string& name, double O::*member, NumericRange range, const std::string& help) && {
    OptionField<O> f{name, OptionType::kReal, range.Text(), help, false, {}, {}, {}};
    f.get = [member](const O& o) { return nlohmann::json(o.*member); };
    f.set = [member](O& o, const nlohmann::json& v) { o.*member = v.get<double>(); };
    f.in_range = [member, range](const O& o) { return range.Contains(o.*member); };
    return Add(std::move(f));
  }
  // A boolean spelled on|off (--spatial off); Switch: a flag without value (--restore).
  OptionTable&& Switch(const std::string& name, bool O::*member, const std::string& help) && {
    return std::move(*this).Flag(name, member, help, true);
  }
  OptionTable&& Flag(const std::string& name, bool O::*member, const std::string& help, bool presence = false) && {
    OptionField<O> f{name, OptionType::kFlag, "on|off", help, presence, {}, {}, {}};
    f.get = [member](const O& o) { return nlohmann::json(o.*member); };
    f.set = [member](O& o, const nlohmann::json& v) { o.*member = v.get<bool>(); };
    f.in_range = [](const O&) { return true; };
    return Add(std::move(f));
  }
  OptionTable&& Text(const std::string& name, std::string O::*member, const std::string& help) && {
    OptionField<O> f{name, OptionType::kText, "", help, false, {}, {}, {}};
    f.get = [member](const O& o) { return nlohmann::json(o.*member); };
    f.set = [member](O& o, const nlohmann::json& v) { o.*member = v.get<std::string>(); };
    f.in_range = [](const O&) { return true; };
    return Add(std::move(f));
  }
  // An enum (or any value type) spelled by names: {{"distance", DeltaMode::kDistance}, ...}.
  template <class E>
  OptionTable&& Choice(const std::string& name, E O::*member, std::vector<std::pair<std::string, E>> names,
                       const std::string& help) && {
    return std::move(*this).ChoiceAt(name, [member](auto& o) -> auto& { return o.*member; }, std::move(names), help);
  }
  // A field of a nested options struct (GraphOptions::prior.wide_credit).
  template <class N, class E>
  OptionTable&& Choice(const std::string& name, N O::*nested, E N::*member,
                       std::vector<std::pair<std::string, E>> names, const std::string& help) && {
    return std::move(*this).ChoiceAt(name, [nested, member](auto& o) -> auto& { return (o.*nested).*member; },
                                     std::move(names), help);
  }
  // Anything else (a value with its own syntax, e.g. "percentile:95"): the caller's functions.
  OptionTable&& Custom(OptionField<O> field) && { return Add(std::move(field)); }

  // Throws Error(kUsage) naming the first field outside its range.
  void Check(const O& options) const {
    for (const auto& f : fields_)
      if (!f.in_range(options))
        throw OptionOutOfRange(scope_, f.name, SpellOptionValue(f.get(options)), f.range, f.help);
  }
  // {name: value} of every field.
  nlohmann::json ToJson(const O& options) const {
    nlohmann::json j = nlohmann::json::object();
    for (const auto& f : fields_) j[f.name] = f.get(options);
    return j;
  }
  // One field from a JSON value or from text (grid values, CLI flags); unknown names and wrong
  // types are usage errors that list what is accepted. Ranges are checked by Check().
  void Set(O& options, const std::string& name, const nlohmann::json& value) const {
    const OptionField<O>& f = Find(name);
    f.set(options, ConvertOptionJson(f.type, value, scope_ + " option '" + name + "'"));
  }
  void SetText(O& options, const std::string& name, const std::string& text) const {
    const OptionField<O>& f = Find(name);
    f.set(options, ParseOptionText(f.type, text, scope_ + " option '" + name + "'"));
  }
  // Every key of a JSON object (e.g. --solver-options), then Check(); options change only when
  // all of it is valid.
  void Apply(O& options, const nlohmann::json& object) const {
    if (object.is_null()) return;
    if (!object.is_object()) throw Error(scope_ + " options must be a JSON object", ExitCode::kUsage);
    O updated = options;
    for (const auto& [key, value] : object.items()) Set(updated, key, value);
    Check(updated);
    options = std::move(updated);
  }
  bool Has(const std::string& name) const {
    for (const auto& f : fields_)
      if (f.name == name) return true;
    return false;
  }
  const OptionField<O>& Find(const std::string& name) const {
    for (const auto& f : fields_)
      if (f.name == name) return f;
    std::string known;
    for (const auto& f : fields_) known += (known.empty() ? "" : ", ") + f.name;
    throw Error(scope_ + ": unknown option '" + name + "' (known: " + known + ")", ExitCode::kUsage);
  }

 private:
  // ref(o) is the field's value (a const or mutable reference, as o is).
  template <class E, class Ref>
  OptionTable&& ChoiceAt(const std::string& name, Ref ref, std::vector<std::pair<std::string, E>> names,
                         const std::string& help) && {
    std::string range;
    for (const auto& [text, value] : names) range += (range.empty() ? "" : "|") + text;
    OptionField<O> f{name, OptionType::kChoice, range, help, false, {}, {}, {}};
    f.get = [ref, names](const O& o) {
      for (const auto& [text, value] : names)
        if (ref(o) == value) return nlohmann::json(text);
      return nlohmann::json(nullptr);
    };
    f.set = [this_scope = scope_, name, ref, names, range](O& o, const nlohmann::json& v) {
      for (const auto& [text, value] : names)
        if (v.get<std::string>() == text) return void(ref(o) = value);
      throw Error(this_scope + " option '" + name + "' must be one of " + range + ", not '" +
                      v.get<std::string>() + "'", ExitCode::kUsage);
    };
    f.in_range = [ref, names](const O& o) {
      for (const auto& entry : names)
        if (ref(o) == entry.second) return true;
      return false;
    };
    return Add(std::move(f));
  }
  OptionTable&& Add(OptionField<O> field) {
    if (Has(field.name)) throw Error(scope_ + ": option '" + field.name + "' declared twice", ExitCode::kInternal);
    fields_.push_back(std::move(field));
    return std::move(*this);
  }

  std::string scope_;
  std::vector<OptionField<O>> fields_;
};

}  // namespace al
