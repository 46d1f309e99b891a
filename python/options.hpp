// Keyword options from the options tables (al/core/option_table.hpp): a keyword argument whose
// name is a field of a table is converted to JSON and handed to OptionTable::Set, and help() shows
// each table's fields with range, default and help. Everything is generic in the options struct:
// a struct that gets a Table() later is picked up by TakeTableOptions with no change here.
#pragma once
#include <sstream>
#include <string>

#include "al/core/option_table.hpp"
#include "python/common.hpp"

namespace al::python {

template <class O>
concept HasOptionTable = requires { O::Table(); };

// JSON of a keyword value for a field: numbers given to a text field (e.g. threshold=0.5) are
// spelled as the CLI would spell them, so Python and the command line accept the same values.
template <class O>
nlohmann::json FieldValue(const OptionField<O>& field, py::handle value) {
  nlohmann::json j = ToJson(value);
  const bool textual = field.type == OptionType::kText || field.type == OptionType::kChoice;
  if (textual && j.is_number()) return FormatOptionNumber(j.get<double>());
  return j;
}

// The keyword of a field in kwargs: its name, or its name with a trailing underscore (PEP 8's
// spelling for names that are Python keywords: lambda_=2). Empty when absent.
inline std::string KeywordOf(const std::string& name, const py::dict& kwargs) {
  if (kwargs.contains(py::str(name))) return name;
  if (kwargs.contains(py::str(name + "_"))) return name + "_";
  return "";
}

// Moves every keyword of `kwargs` that `table` declares into `options` (Set, then Check), and
// removes it from kwargs. Throws al::Error (usage) for a wrong type or a value out of range.
template <class O>
void TakeOptions(const OptionTable<O>& table, O& options, py::dict& kwargs) {
  nlohmann::json values = nlohmann::json::object();
  for (const auto& field : table.fields()) {
    const std::string keyword = KeywordOf(field.name, kwargs);
    if (keyword.empty()) continue;
    const py::str key(keyword);
    values[field.name] = FieldValue(field, kwargs[key]);
    PyDict_DelItem(kwargs.ptr(), key.ptr());
  }
  if (!values.empty()) table.Apply(options, values);
}

template <class O>
void TakeTableOptions(O& options, py::dict& kwargs) {
  if constexpr (HasOptionTable<O>) TakeOptions(O::Table(), options, kwargs);
}

// "name (range, default D): help" per field, for docstrings.
template <class O>
std::string OptionsDoc(const OptionTable<O>& table, const O& defaults = O{}) {
  std::ostringstream s;
  s << table.scope() << " options:\n";
  for (const auto& f : table.fields()) {
    s << "    " << f.name << " (" << (f.range.empty() ? "text" : f.range) << ", default "
      << SpellOptionValue(f.get(defaults)) << "): " << f.help << "\n";
  }
  return s.str();
}

template <class O>
std::string TableDoc() {
  if constexpr (HasOptionTable<O>) return OptionsDoc(O::Table());
  return "";
}

// Names a table declares (for the error that lists every accepted keyword).
template <class O>
std::string TableNames(const OptionTable<O>& table) {
  std::string names;
  for (const auto& f : table.fields()) names += (names.empty() ? "" : ", ") + f.name;
  return names;
}

// "label: name, name; " for a struct with a table, "" for one without (yet).
template <class O>
std::string TableNamesIfAny(const std::string& label) {
  if constexpr (HasOptionTable<O>) return label + ": " + TableNames(O::Table()) + "; ";
  return "";
}

}  // namespace al::python
