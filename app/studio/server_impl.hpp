#pragma once
// What the route files share (server.cpp, job_routes.cpp): the state behind the routes and the helpers
// that answer in JSON.

#include <httplib.h>

#include <atomic>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "jobs.hpp"
#include "models.hpp"
#include "preview.hpp"
#include "server.hpp"

namespace studio {

struct Server::Impl {
  explicit Impl(ServerConfig c);
  ServerConfig config;
  httplib::Server http;
  Models models;
  Previews previews;
  Jobs jobs;
  std::vector<std::string> hosts;  // the Host values accepted
  std::atomic<bool> stopping{false};
  int port = 0;
  double start_scale = 1.0;
};

// {"error": message, "option": name} with the status.
void answer_error(httplib::Response& res, int status, const std::string& message,
                  const std::string& option = {});
void answer_json(httplib::Response& res, const nlohmann::json& body, int status = 200);
// A library error as the API answers it: 400 for a bad option or input, 409 for a cancelled run, 500
// for the rest.
void answer_library_error(httplib::Response& res, const poreshell::Error& e);

// The job routes: make, status, events, files, cancel.
void add_job_routes(Server::Impl& impl);

}  // namespace studio
