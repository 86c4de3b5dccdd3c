#pragma once
// The studio's access token: every request carries it (docs/studio.md "Safety").

#include <string>
#include <string_view>

namespace studio {

// 256 random bits from the kernel (getrandom), as 64 hex digits. Throws std::runtime_error when the
// kernel gives none: a guessable token would defeat the check, so the studio does not start.
std::string random_token();

// a == b in a time that does not depend on where they differ (no timing oracle for the token).
bool same_token(std::string_view a, std::string_view b);

}  // namespace studio
