#include "guard.hpp"

namespace studio {

std::vector<std::string> allowed_hosts(int port, std::string_view extra_host) {
  std::vector<std::string> names{"localhost", "127.0.0.1", "[::1]"};
  if (!extra_host.empty()) {
    // An IPv6 address is written in brackets in a Host header. (Appended piecewise: g++ 12's -Wrestrict
    // misfires on operator+ of short strings.)
    std::string name;
    const bool v6 = extra_host.find(':') != std::string_view::npos;
    if (v6) name += '[';
    name += extra_host;
    if (v6) name += ']';
    names.push_back(std::move(name));
  }
  const std::string number = std::to_string(port);
  for (std::string& name : names) {
    name += ':';
    name += number;
  }
  return names;
}

std::string cookie_value(std::string_view cookie_header, std::string_view name) {
  while (!cookie_header.empty()) {
    const std::size_t end = cookie_header.find(';');
    std::string_view item = cookie_header.substr(0, end);
    while (!item.empty() && item.front() == ' ') item.remove_prefix(1);
    if (item.size() > name.size() && item.substr(0, name.size()) == name && item[name.size()] == '=')
      return std::string(item.substr(name.size() + 1));
    if (end == std::string_view::npos) break;
    cookie_header.remove_prefix(end + 1);
  }
  return {};
}

std::string request_token(std::string_view header, std::string_view query, std::string_view cookie_header) {
  if (!header.empty()) return std::string(header);
  if (!query.empty()) return std::string(query);
  return cookie_value(cookie_header, "poreshell_token");
}

}  // namespace studio
