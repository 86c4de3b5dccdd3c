#include "server.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "guard.hpp"
#include "page.hpp"
#include "poreshell/option_table.hpp"
#include "server_impl.hpp"
#include "token.hpp"

namespace studio {

namespace fs = std::filesystem;
using httplib::Request;
using httplib::Response;

Server::Impl::Impl(ServerConfig c)
    : config(std::move(c)), models(config.workdir / "models"), jobs(config.workdir / "jobs") {}

// Debian's httplib compresses bodies of "application/json" and "text/..." with brotli at its highest
// quality when the browser accepts it: 8 s for a bunny's 4 MB preview against 0.003 s for the bytes on
// the loopback. The charset keeps JSON out of its list; the page goes out through a content provider,
// which it leaves alone.
void answer_json(Response& res, const nlohmann::json& body, int status) {
  res.status = status;
  res.set_content(body.dump(), "application/json; charset=utf-8");
}

void answer_error(Response& res, int status, const std::string& message, const std::string& option) {
  nlohmann::json body = {{"error", message}};
  if (!option.empty()) body["option"] = option;
  answer_json(res, body, status);
}

void answer_library_error(Response& res, const poreshell::Error& e) {
  switch (e.code()) {
    case poreshell::ErrorCode::invalid_option:
    case poreshell::ErrorCode::invalid_input:
    case poreshell::ErrorCode::too_large:
      answer_error(res, 400, e.what(), e.option());
      return;
    case poreshell::ErrorCode::cancelled:
      answer_error(res, 409, e.what());
      return;
    default:
      answer_error(res, 500, e.what(), e.option());
  }
}

namespace {

// Every request: the Host header against DNS rebinding, then the token (docs/studio.md "Safety").
httplib::Server::HandlerResponse guard(const Server::Impl& impl, const Request& req, Response& res) {
  const std::string host = req.get_header_value("Host");
  if (std::find(impl.hosts.begin(), impl.hosts.end(), host) == impl.hosts.end()) {
    answer_error(res, 403, "the Host header '" + host + "' is not this studio's address");
    return httplib::Server::HandlerResponse::Handled;
  }
  const std::string token = request_token(req.get_header_value("X-Poreshell-Token"),
                                          req.get_param_value("token"), req.get_header_value("Cookie"));
  if (!same_token(token, impl.config.token)) {
    answer_error(res, 403, "missing or wrong token: open the address the studio printed");
    return httplib::Server::HandlerResponse::Handled;
  }
  return httplib::Server::HandlerResponse::Unhandled;
}

nlohmann::json option_table_json() {
  nlohmann::json table = nlohmann::json::array();
  for (const poreshell::OptionInfo& o : poreshell::option_table()) {
    static constexpr const char* kTypes[] = {"number",  "integer", "boolean", "choice", "text",
                                             "numbers", "spheres", "boxes",   "grade"};
    table.push_back({{"name", o.name},
                     {"group", o.group},
                     {"type", kTypes[static_cast<int>(o.type)]},
                     {"unit", o.unit},
                     {"min", o.min},
                     {"max", o.max},
                     {"min_open", o.min_open},
                     {"max_open", o.max_open},
                     {"help", o.help},
                     {"choices", o.choices}});
  }
  return table;
}

nlohmann::json model_json(const Model& m, bool with_mesh);

// POST /api/model?name=FILE&units=U: the body streamed into a file named here, then read.
void upload_model(Server::Impl& impl, const Request& req, Response& res,
                  const httplib::ContentReader& reader) {
  const std::string name = req.get_param_value("name");
  const std::string ext = model_extension(name);
  if (ext.empty()) {
    answer_error(
        res, 400,
        "name '" + name + "' has no model extension: .stl, .obj, .ply, .off, .3mf, .xyz, .txt or .pts");
    return;
  }
  poreshell::Unit unit{};
  try {
    unit = parse_unit(req.get_param_value("units"));
  } catch (const std::invalid_argument& e) {
    answer_error(res, 400, e.what(), "units");
    return;
  }
  const fs::path path = impl.models.new_path(ext);
  bool written = true;
  {
    std::ofstream out(path, std::ios::binary);
    const bool read = reader([&](const char* data, std::size_t length) {
      out.write(data, static_cast<std::streamsize>(length));
      return written = static_cast<bool>(out);
    });
    written = read && written;
  }
  if (!written) {
    std::error_code ignored;
    fs::remove(path, ignored);
    if (res.status != 413) answer_error(res, 400, "the upload was cut short or could not be stored");
    return;
  }
  try {
    answer_json(res, model_json(*impl.models.add(path, name, unit), true));
  } catch (const poreshell::Error& e) {
    answer_error(res, 400, e.what(), e.option());
  }
}

void add_routes(Server::Impl& impl) {
  auto& http = impl.http;
  http.Get("/", [&impl](const Request& req, Response& res) {
    // The page's later requests (its event streams among them) carry the token as this cookie.
    if (req.has_param("token"))
      res.set_header("Set-Cookie",
                     "poreshell_token=" + impl.config.token + "; Path=/; HttpOnly; SameSite=Strict");
    res.set_header("Cache-Control", "no-store");
    const std::string& page = studio_page();
    res.set_content_provider(page.size(), "text/html; charset=utf-8",
                             [&page](std::size_t offset, std::size_t length, httplib::DataSink& sink) {
                               return sink.write(page.data() + offset,
                                                 std::min(length, page.size() - offset));
                             });
  });
  http.Get("/api/health", [&impl](const Request&, Response& res) {
    const auto model = impl.models.get(0);
    answer_json(res, {{"version", poreshell::version()},
                      {"model", model ? nlohmann::json(model->id) : nlohmann::json(nullptr)},
                      {"scale", impl.start_scale}});
  });
  http.Get("/api/options", [](const Request&, Response& res) {
    answer_json(res, {{"options", option_table_json()},
                      {"defaults", nlohmann::json::parse(poreshell::options_to_json(poreshell::Options{}))}});
  });
  http.Post("/api/model", [&impl](const Request& req, Response& res, const httplib::ContentReader& reader) {
    upload_model(impl, req, res, reader);
  });
  http.Get(R"(/api/model/(\d{1,9}))", [&impl](const Request& req, Response& res) {
    const auto model = impl.models.get(std::stoi(req.matches[1]));
    if (!model) return answer_error(res, 404, "no such model");
    answer_json(res, model_json(*model, true));
  });
  // The model's file as uploaded (the page embeds it in a saved project).
  http.Get(R"(/api/model/(\d{1,9})/file)", [&impl](const Request& req, Response& res) {
    const auto model = impl.models.get(std::stoi(req.matches[1]));
    std::ifstream in(model ? model->path : fs::path(), std::ios::binary);
    if (!model || !in) return answer_error(res, 404, "no such model");
    std::ostringstream bytes;
    bytes << in.rdbuf();
    res.set_content(bytes.str(), "application/octet-stream");
  });
  http.Post("/api/preview", [&impl](const Request& req, Response& res) {
    try {
      answer_json(res, impl.previews.run(parse_run_request(req.body, impl.models)));
    } catch (const poreshell::Error& e) {
      answer_library_error(res, e);
    }
  });
  add_job_routes(impl);
  // Bodies for the statuses httplib answers itself (no route, too large).
  http.set_error_handler([](const Request&, Response& res) {
    if (!res.body.empty()) return;
    if (res.status == 413) return answer_error(res, 413, "the upload is larger than the studio's limit");
    answer_error(res, res.status, res.status == 404 ? "not found" : "request refused");
  });
}

nlohmann::json model_json(const Model& m, bool with_mesh) {
  nlohmann::json body = {{"id", m.id},
                         {"name", m.name},
                         {"units", poreshell::to_string(m.unit)},
                         {"size_mm", {m.max[0] - m.min[0], m.max[1] - m.min[1], m.max[2] - m.min[2]}},
                         {"min_mm", {m.min[0], m.min[1], m.min[2]}},
                         {"vertices", m.vertices},
                         {"triangles", m.triangles},
                         {"kind", std::holds_alternative<poreshell::MeshInput>(m.input) ? "mesh" : "points"}};
  if (with_mesh) body["mesh"] = model_mesh_json(m);
  return body;
}

}  // namespace

Server::Server(ServerConfig config) : impl_(std::make_unique<Impl>(std::move(config))) {
  if (impl_->config.token.empty()) impl_->config.token = random_token();
  fs::create_directories(impl_->config.workdir / "models");
  fs::create_directories(impl_->config.workdir / "jobs");
  impl_->http.set_payload_max_length(impl_->config.upload_limit);
  // Debian's build leaves Nagle on: a small answer then waits 40 ms for the client's delayed ACK between
  // its header and its body (bench/studio/http_libraries: 43 ms a /health request, 0.1 ms with this).
  impl_->http.set_tcp_nodelay(true);
  impl_->http.set_pre_routing_handler(
      [impl = impl_.get()](const Request& req, Response& res) { return guard(*impl, req, res); });
  add_routes(*impl_);
}

Server::~Server() {
  stop();
}

int Server::bind() {
  const int port =
      impl_->config.port == 0
          ? impl_->http.bind_to_any_port(impl_->config.host)
          : (impl_->http.bind_to_port(impl_->config.host, impl_->config.port) ? impl_->config.port : -1);
  if (port <= 0)
    throw std::runtime_error("cannot listen on " + impl_->config.host + ":" +
                             std::to_string(impl_->config.port));
  impl_->port = port;
  const bool loopback = impl_->config.host == "127.0.0.1" || impl_->config.host == "localhost";
  impl_->hosts = allowed_hosts(port, loopback ? std::string_view{} : std::string_view{impl_->config.host});
  return port;
}

void Server::open_model(const fs::path& path, const std::string& units) {
  const std::string name = path.filename().string();
  const std::string ext = model_extension(name);
  if (ext.empty())
    throw poreshell::Error(poreshell::ErrorCode::invalid_input, "'" + name + "' has no model extension");
  const fs::path copy = impl_->models.new_path(ext);
  fs::copy_file(path, copy, fs::copy_options::overwrite_existing);
  impl_->models.add(copy, name, parse_unit(units));
}

void Server::set_scale(double scale) {
  impl_->start_scale = scale;
}

bool Server::run() {
  return impl_->http.listen_after_bind();
}

void Server::stop() {
  impl_->stopping = true;
  impl_->previews.stop();
  impl_->jobs.shutdown();
  impl_->http.stop();
}

const std::string& Server::token() const {
  return impl_->config.token;
}

int Server::port() const {
  return impl_->port;
}

}  // namespace studio
