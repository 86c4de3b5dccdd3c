#pragma once
// 3MF packages written by hand, for the readers' tests: a ZIP archive of stored (uncompressed) entries
// holding the content types, the relationships and one model part.

#include <string>
#include <utility>
#include <vector>

namespace poreshell::test_support {

// A ZIP archive of stored entries (name, bytes), in order.
std::string stored_zip(const std::vector<std::pair<std::string, std::string>>& entries);

// A 3MF package whose 3D/3dmodel.model is `model_xml`, as given.
std::string package_3mf(const std::string& model_xml);

}  // namespace poreshell::test_support
