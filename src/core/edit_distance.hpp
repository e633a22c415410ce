// Edit distance between short words, and "did you mean" suggestions built on it.
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace imx {

// Optimal-string-alignment distance: insertions, deletions, substitutions and swaps of
// neighbours each cost 1.
size_t edit_distance(std::string_view a, std::string_view b);

// The candidate closest to `word` when it is a plausible misspelling: equal ignoring case,
// or within edit distance 2 (ignoring case) and shorter than the word itself.
std::optional<std::string> closest_match(std::string_view word,
                                         const std::vector<std::string>& candidates);

// " (did you mean 'x'?)" for the closest match, or "" when there is none.
std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates);

}  // namespace imx
