#pragma once
// A studio project: one JSON file with the model (a path or its bytes embedded), every setting by the
// library's option names, the keep-outs among them, and the painted mask (docs/studio.md "Projects").
// The page writes it; `poreshell --project FILE -o OUT` runs it and writes what the page's Make writes.

#include <filesystem>

#include "poreshell/poreshell.hpp"

namespace studio {

struct Project {
  poreshell::Input input;  // the mask, when painted, as its vertex field
  poreshell::Options options;
};

// Throws poreshell::Error: invalid_input for a file that is no project or a model that cannot be read,
// invalid_option naming the option for a bad setting. A relative model path is taken from the project's
// folder.
Project load_project(const std::filesystem::path& file);

}  // namespace studio
