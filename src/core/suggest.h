#pragma once
// "Did you mean": the closest of a list of names to a misspelt one, for error messages about
// option keys, scene-file parameters and directives.

#include <string>
#include <string_view>
#include <vector>

namespace rl {

// Edit distance (insertions, deletions, substitutions, and swaps of neighbours: optimal string
// alignment), case-insensitive.
int edit_distance(std::string_view a, std::string_view b);

// The candidate closest to `word` if it is close enough to be the intended one (at most a third of
// the word's letters wrong, at least 1, at most 3), else "". Ties keep the first candidate.
std::string closest_name(std::string_view word, const std::vector<std::string>& candidates);

// " (did you mean 'x'?)" for the closest candidate, or "" when none is close: to append to an error.
std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates);

}  // namespace rl
