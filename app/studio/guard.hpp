#pragma once
// Who may talk to the studio: the right Host header (against DNS rebinding) and the token.

#include <string>
#include <string_view>
#include <vector>

namespace studio {

// The Host values a request may carry: localhost, 127.0.0.1 and [::1] with the port, and `extra_host`
// (the --host address, when one was given) with it.
std::vector<std::string> allowed_hosts(int port, std::string_view extra_host = {});

// The token of a request: the X-Poreshell-Token header, else ?token=, else the poreshell_token cookie.
std::string request_token(std::string_view header, std::string_view query, std::string_view cookie_header);

// The cookie's value in a Cookie header ("a=1; poreshell_token=X"), or empty.
std::string cookie_value(std::string_view cookie_header, std::string_view name);

}  // namespace studio
