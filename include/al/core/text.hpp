// Parsing helpers for the small list syntaxes on the command line (--grid "k=4,6;delta=0.8").
#pragma once
#include <string>
#include <vector>

namespace al {

// s without leading/trailing spaces, tabs and line breaks.
std::string Trim(const std::string& s);

// The parts of s between sep, each trimmed; a trailing sep yields a final empty part, so callers
// can reject or skip empty items explicitly.
std::vector<std::string> SplitTrimmed(const std::string& s, char sep);

// A finite number spelled exactly by text (after trimming); throws al::Error (usage)
// "--grid: KEY: 'TEXT' is not a finite number" otherwise.
double ParseGridNumber(const std::string& key, const std::string& text);

}  // namespace al
