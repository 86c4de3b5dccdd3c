#pragma once
// What the command line needs besides its option table: flag names in the library's messages, number
// lists, "did you mean", the estimate and the viewer's files.

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

#include "poreshell/poreshell.hpp"

inline constexpr int kExitFailure = 1;
inline constexpr int kExitUsage = 2;

// The library names options by their API names in backquotes (`hole_diameter`); here they are flags.
std::string with_flags(std::string message);

// Like CLI::PositiveNumber / NonNegativeNumber, but with a message that states the rule instead of
// printing the range up to DBL_MAX.
CLI::Validator number_above(double low, bool inclusive);

// "X,Y,Z,..." with exactly `count` numbers, or nothing.
std::optional<std::vector<double>> numbers(const std::string& text, std::size_t count);

// "unknown argument '--resolutoin' (did you mean --resolution?)": the flag nearest by edit distance.
std::string unknown_argument_message(const CLI::App& app, const std::string& argument);

// The report's name of an input: its file, or the shape.
std::string input_name(const poreshell::Input& input);

// The run's estimate, its warnings naming flags.
poreshell::Estimate estimate_with_flags(const poreshell::Prepared& prepared);

// Every output the command would write, checked before any work (issue 47): each folder exists and takes
// files, no two outputs are the same file (after resolving links and ".."), and none is the input.
// Throws poreshell::Error for a path that cannot be written, UsageError for a clash.
struct Command;
void check_output_paths(const Command& command);

// One line on stderr and the usage exit code.
int usage_error(const std::string& message);

// The viewer page and its picture; a picture alone is taken of a page in a temporary file.
void save_views(const std::string& html, const std::string& png, const poreshell::Result& result,
                const poreshell::Options& options, const poreshell::Input& input);
