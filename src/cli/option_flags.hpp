// CLI flags generated from an options table (al/core/option_table.hpp): one flag per field, named
// --field-name, its help with the range and the default, parsed by the table so that the CLI, the
// sweep grid and the solver-options JSON accept exactly the same spellings. Ranges are checked by
// the library's Check() when the command runs, so every entry point reports the same message.
#pragma once
#include <algorithm>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "al/core/option_table.hpp"

namespace al::cli {

// What --help shows after the flag: INT, NUMBER, on|off, distance|cosine, or the custom range.
template <class O>
std::string TypeName(const OptionField<O>& field) {
  switch (field.type) {
    case OptionType::kInt: return "INT";
    case OptionType::kReal: return "NUMBER";
    case OptionType::kFlag:
    case OptionType::kChoice: return field.range;
    case OptionType::kText: return field.range.empty() ? "TEXT" : field.range;
  }
  return "TEXT";
}

// A choice that names "off" among its values (auto|on|off): it gets a --no- flag, as a flag does.
template <class O>
bool HasOffChoice(const OptionField<O>& field) {
  if (field.type != OptionType::kChoice) return false;
  const std::string names = "|" + field.range + "|";
  return names.find("|off|") != std::string::npos;
}

// Adds every field of `table` (except those named in `skip`) to `app`, bound to `options`, whose
// values at this call are the defaults shown. `options` must outlive parsing.
template <class O>
void AddOptionFlags(CLI::App& app, const OptionTable<O>& table, O& options, const std::string& group,
                    const std::vector<std::string>& skip = {}) {
  for (const auto& field : table.fields()) {
    if (std::find(skip.begin(), skip.end(), field.name) != skip.end()) continue;
    const std::string name = field.name, flag = field.Flag();
    auto store = [&table, &options, name, flag](const nlohmann::json& value, bool text) {
      try {
        text ? table.SetText(options, name, value.get<std::string>()) : table.Set(options, name, value);
      } catch (const Error& e) {
        throw CLI::ValidationError(flag, e.what());
      }
    };
    std::string help = field.help;
    if (field.presence) {
      app.add_flag_callback(flag, [store] { store(true, false); }, help)->group(group);
      continue;
    }
    if (field.type == OptionType::kFlag || HasOffChoice(field)) {  // --spatial off = --no-spatial
      std::string no = "--no-" + flag.substr(2);
      app.add_flag_callback(no, [store] { store(false, false); }, "same as " + flag + " off")->group(group);
    }
    const bool numeric = field.type == OptionType::kInt || field.type == OptionType::kReal;
    if (numeric && !field.range.empty()) help += "; " + field.range;
    app.add_option_function<std::string>(flag, [store](const std::string& s) { store(s, true); }, help)
        ->type_name(TypeName(field))
        ->default_str(SpellOptionValue(field.get(options)))
        ->group(group);
  }
}

}  // namespace al::cli
