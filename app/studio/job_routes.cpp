// The job routes of docs/studio.md: POST /api/make, GET /api/jobs/ID (and its events and files),
// DELETE /api/jobs/ID.

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "server_impl.hpp"

namespace studio {

using httplib::Request;
using httplib::Response;

namespace {

nlohmann::json status_json(const Job& job, const JobStatus& s, bool with_report) {
  nlohmann::json body = {
      {"job", job.id()},        {"state", to_string(s.state)},
      {"fraction", s.fraction}, {"eta", s.eta < 0.0 ? nlohmann::json(nullptr) : nlohmann::json(s.eta)},
      {"stage", s.stage},       {"files", s.files}};
  if (!s.error.empty()) body["error"] = s.error;
  if (!s.error_option.empty()) body["option"] = s.error_option;
  if (with_report && !s.report.empty()) body["report"] = nlohmann::json::parse(s.report, nullptr, false);
  return body;
}

std::shared_ptr<Job> find_job(Server::Impl& impl, const Request& req, Response& res) {
  auto job = impl.jobs.get(std::stoi(req.matches[1]));
  if (!job) answer_error(res, 404, "no such job");
  return job;
}

void make(Server::Impl& impl, const Request& req, Response& res) {
  try {
    RunRequest request = parse_run_request(req.body, impl.models);
    poreshell::Options checked = request.options;  // the mask checked now, not as a failed job
    (void)masked_input(request.model->input, request.mask, checked);
    const auto job = impl.jobs.start(std::move(request));
    answer_json(res, {{"job", job->id()}});
  } catch (const Busy& e) {
    answer_error(res, 409, e.what());
  } catch (const poreshell::Error& e) {
    answer_library_error(res, e);
  }
}

// Progress as Server-Sent Events: one `data:` line of the status's JSON a change (at most 5 a second),
// the last one once the job has finished. A client that goes away only ends its stream.
void events(Server::Impl& impl, const Request& req, Response& res) {
  const auto job = find_job(impl, req, res);
  if (!job) return;
  res.set_header("Cache-Control", "no-store");
  auto version = std::make_shared<long>(-1);
  res.set_chunked_content_provider(
      "text/event-stream", [&impl, job, version](std::size_t, httplib::DataSink& sink) {
        const JobStatus s = job->wait_change(*version, 0.2);
        if (s.version != *version || s.finished()) {
          *version = s.version;
          const std::string event = "data: " + status_json(*job, s, false).dump() + "\n\n";
          if (!sink.write(event.data(), event.size())) return false;
        }
        if (s.finished() || impl.stopping) sink.done();
        return true;
      });
}

void file(Server::Impl& impl, const Request& req, Response& res) {
  const auto job = find_job(impl, req, res);
  if (!job) return;
  // Only a name the job lists, compared as given (after httplib's decoding): "..", "/" and "%2F" never
  // match one, so no path from the client reaches the file system.
  const std::string name = req.matches[2];
  const JobStatus s = job->status();
  if (std::find(s.files.begin(), s.files.end(), name) == s.files.end())
    return answer_error(res, 404, "job " + std::to_string(job->id()) + " has no file '" + name + "'");
  std::ifstream in(job->folder() / name, std::ios::binary);
  if (!in) return answer_error(res, 404, "the file is gone");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  res.set_header("Content-Disposition", "attachment; filename=\"" + name + "\"");
  // Not "text/csv" nor bare "application/json": httplib would brotli them (server.cpp, answer_json).
  res.set_content(bytes.str(),
                  name.ends_with(".json") ? "application/json; charset=utf-8" : "application/octet-stream");
}

}  // namespace

void add_job_routes(Server::Impl& impl) {
  auto& http = impl.http;
  http.Post("/api/make", [&impl](const Request& req, Response& res) { make(impl, req, res); });
  http.Get(R"(/api/jobs/(\d{1,9}))", [&impl](const Request& req, Response& res) {
    if (const auto job = find_job(impl, req, res)) answer_json(res, status_json(*job, job->status(), true));
  });
  http.Get(R"(/api/jobs/(\d{1,9})/events)",
           [&impl](const Request& req, Response& res) { events(impl, req, res); });
  http.Get(R"(/api/jobs/(\d{1,9})/files/(.+))",
           [&impl](const Request& req, Response& res) { file(impl, req, res); });
  http.Delete(R"(/api/jobs/(\d{1,9}))", [&impl](const Request& req, Response& res) {
    const auto job = find_job(impl, req, res);
    if (!job) return;
    job->cancel();
    answer_json(res, status_json(*job, job->status(), false));
  });
}

}  // namespace studio
