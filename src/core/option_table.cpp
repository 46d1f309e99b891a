#include "al/core/option_table.hpp"

#include <charconv>
#include <cmath>
#include <cstdint>

#include "al/core/text.hpp"

namespace al {
namespace {

bool ParseFinite(const std::string& text, double& value) {
  const std::string t = Trim(text);
  std::size_t used = 0;
  try {
    value = std::stod(t, &used);
  } catch (const std::exception&) {
    return false;
  }
  return !t.empty() && used == t.size() && std::isfinite(value);
}

bool ParseFlag(const std::string& text, bool& value) {
  const std::string t = Trim(text);
  if (t == "on" || t == "true" || t == "1" || t == "yes") return value = true, true;
  if (t == "off" || t == "false" || t == "0" || t == "no") return value = false, true;
  return false;
}

nlohmann::json IntegralOrThrow(double v, const std::string& what, const std::string& spelled) {
  // 2^53: every integer below is exact in a double, so the check below is exact too.
  if (std::fabs(v) > 9007199254740992.0 || std::floor(v) != v)
    throw Error(what + " must be an integer, not " + spelled, ExitCode::kUsage);
  return nlohmann::json(static_cast<std::int64_t>(v));
}

}  // namespace

std::string FormatOptionNumber(double value) {
  char buffer[64];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
  return ec == std::errc() ? std::string(buffer, end) : std::to_string(value);
}

std::string NumericRange::Text() const {
  const bool low = std::isfinite(lo), high = std::isfinite(hi);
  std::string text;
  if (!low && !high) {
    text = "finite numbers";
  } else if (!high) {
    text.append(lo_open ? "> " : ">= ").append(FormatOptionNumber(lo));
  } else if (!low) {
    text.append(hi_open ? "< " : "<= ").append(FormatOptionNumber(hi));
  } else {
    text.append(lo_open ? "(" : "[").append(FormatOptionNumber(lo)).append(", ");
    text.append(FormatOptionNumber(hi)).append(hi_open ? ")" : "]");
  }
  return text;
}

std::string SpellOptionValue(const nlohmann::json& value) {
  if (value.is_boolean()) return value.get<bool>() ? "on" : "off";
  if (value.is_number()) return FormatOptionNumber(value.get<double>());
  return value.is_string() ? value.get<std::string>() : value.dump();
}

nlohmann::json ParseOptionText(OptionType type, const std::string& text, const std::string& what) {
  double number = 0.0;
  bool flag = false;
  switch (type) {
    case OptionType::kInt:
      if (!ParseFinite(text, number)) throw Error(what + ": '" + text + "' is not a number", ExitCode::kUsage);
      return IntegralOrThrow(number, what, "'" + text + "'");
    case OptionType::kReal:
      if (!ParseFinite(text, number))
        throw Error(what + ": '" + text + "' is not a finite number", ExitCode::kUsage);
      return nlohmann::json(number);
    case OptionType::kFlag:
      if (!ParseFlag(text, flag))
        throw Error(what + ": '" + text + "' is not on|off|true|false|1|0", ExitCode::kUsage);
      return nlohmann::json(flag);
    case OptionType::kText:
    case OptionType::kChoice:
      break;
  }
  return nlohmann::json(Trim(text));
}

nlohmann::json ConvertOptionJson(OptionType type, const nlohmann::json& value, const std::string& what) {
  switch (type) {
    case OptionType::kInt:
      if (!value.is_number()) throw Error(what + " must be an integer, not " + value.dump(), ExitCode::kUsage);
      return IntegralOrThrow(value.get<double>(), what, value.dump());
    case OptionType::kReal:
      if (!value.is_number()) throw Error(what + " must be a number, not " + value.dump(), ExitCode::kUsage);
      return nlohmann::json(value.get<double>());
    case OptionType::kFlag:
      if (!value.is_boolean()) throw Error(what + " must be true or false, not " + value.dump(), ExitCode::kUsage);
      return value;
    case OptionType::kChoice:  // a choice with on|off among its names takes a boolean too
      if (value.is_boolean()) return nlohmann::json(value.get<bool>() ? "on" : "off");
      break;
    case OptionType::kText:
      break;
  }
  if (!value.is_string()) throw Error(what + " must be a string, not " + value.dump(), ExitCode::kUsage);
  return value;
}

void CheckOptionRange(const std::string& scope, const std::string& name, double value, const NumericRange& range,
                      const std::string& help) {
  if (!range.Contains(value)) throw OptionOutOfRange(scope, name, FormatOptionNumber(value), range.Text(), help);
}

Error OptionOutOfRange(const std::string& scope, const std::string& name, const std::string& value,
                       const std::string& range, const std::string& help) {
  const bool interval = range.starts_with('[') || range.starts_with('(');
  return Error(scope + " option '" + name + "' = " + value + " must be " + (interval ? "in " : "") + range + " (" +
                   help + ")",
               ExitCode::kUsage);
}

}  // namespace al
