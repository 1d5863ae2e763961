// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "studio/server.h"

#include <atomic>
#include <chrono>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <optional>
#include <system_error>
#include <thread>
#include <vector>

#include "ramiform/core/errors.h"
#include "ramiform/core/numbers.h"
#include "ramiform/script/script.h"
#include "studio/assets.h"
#include "studio/line_views.h"
#include "studio/runs.h"
#include "studio/util.h"

// Last: it includes <resolv.h>, whose `_res` macro breaks Eigen's headers.
#include <httplib.h>

namespace ramiform::studio {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kCookie = "ramiform_studio";
constexpr const char* kJson = "application/json";
/// Worker threads of the HTTP server (requests are short; runs have their own thread).
constexpr std::size_t kHttpThreads = 4;
constexpr int kSocketTimeoutSeconds = 5;
/// Most params a run may set.
constexpr std::size_t kMaxParams = 1000;

void send_json(httplib::Response& res, const json& body, int status = 200) {
  res.status = status;
  // Replacing invalid UTF-8 (a script's raw bytes in a message) instead of throwing.
  res.set_content(body.dump(-1, ' ', false, json::error_handler_t::replace), kJson);
}

void send_error(httplib::Response& res, int status, const std::string& message) {
  send_json(res, {{"error", message}}, status);
}

// The value of cookie `name` in a Cookie header ("a=1; b=2"), or "".
std::string cookie_value(const std::string& header, const std::string& name) {
  std::size_t at = 0;
  while (at < header.size()) {
    std::size_t end = header.find(';', at);
    if (end == std::string::npos) end = header.size();
    std::string_view part(header.data() + at, end - at);
    while (!part.empty() && part.front() == ' ') part.remove_prefix(1);
    if (part.size() > name.size() && part.substr(0, name.size()) == name &&
        part[name.size()] == '=') {
      return std::string(part.substr(name.size() + 1));
    }
    at = end + 1;
  }
  return {};
}

const StudioAsset* find_asset(std::string_view path) {
  for (const StudioAsset& a : studio_assets()) {
    if (a.path == path) return &a;
  }
  return nullptr;
}

void send_asset(httplib::Response& res, const StudioAsset& asset) {
  res.status = 200;
  res.set_content(reinterpret_cast<const char*>(asset.data.data()), asset.data.size(),
                  std::string(asset.mime).c_str());
  res.set_header("Cache-Control", "no-cache");
}

std::optional<json> parse_body(const httplib::Request& req, httplib::Response& res) {
  json body = json::parse(req.body, nullptr, false);
  if (body.is_discarded() || !body.is_object()) {
    send_error(res, 400, "the body must be a JSON object");
    return std::nullopt;
  }
  return body;
}

std::optional<std::array<double, 3>> vec3(const json& v) {
  if (!v.is_array() || v.size() != 3) return std::nullopt;
  std::array<double, 3> out{};
  for (std::size_t i = 0; i < 3; ++i) {
    if (!v[i].is_number()) return std::nullopt;
    out[i] = v[i].get<double>();
  }
  return out;
}

std::string read_text(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw InputError(path, 0, "cannot read the script");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "cannot read the script");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (text.size() > kMaxScript) {
    throw InputError(path, 0, "the script is larger than " + std::to_string(kMaxScript) + " bytes");
  }
  return text;
}

}  // namespace

struct StudioServer::Impl {
  StudioOptions options;
  std::string script;
  std::string script_name;
  std::string info;  // GET /api/info's body, made once
  httplib::Server http;
  std::atomic<int> port{0};
  std::thread thread;
  std::unique_ptr<RunManager> runs;
  std::unique_ptr<LineViews> lines;

  [[nodiscard]] std::vector<std::string> allowed_hosts() const {
    const std::string p = ":" + std::to_string(port.load());
    std::vector<std::string> hosts = {"127.0.0.1" + p, "localhost" + p, "[::1]" + p};
    const std::string& l = options.listen;
    hosts.push_back((l.find(':') != std::string::npos ? "[" + l + "]" : l) + p);
    return hosts;
  }

  [[nodiscard]] bool host_ok(const std::string& host) const {
    for (const std::string& h : allowed_hosts()) {
      if (host == h) return true;
    }
    return false;
  }

  [[nodiscard]] bool origin_ok(const std::string& origin) const {
    for (const std::string& h : allowed_hosts()) {
      if (origin == "http://" + h) return true;
    }
    return false;
  }

  [[nodiscard]] bool authorized(const httplib::Request& req) const {
    const std::string header = req.get_header_value("X-Ramiform-Token");
    if (!header.empty()) return same_token(header, options.token);
    return same_token(cookie_value(req.get_header_value("Cookie"), kCookie), options.token);
  }

  // Host, Origin and the token, before any route: 403 JSON when one fails.
  httplib::Server::HandlerResponse check(const httplib::Request& req, httplib::Response& res) {
    if (req.get_header_value_count("Host") != 1 || !host_ok(req.get_header_value("Host"))) {
      send_error(res, 403, "the Host header must name this server");
      return httplib::Server::HandlerResponse::Handled;
    }
    if (req.has_header("Origin") &&
        (req.get_header_value_count("Origin") != 1 || !origin_ok(req.get_header_value("Origin")))) {
      send_error(res, 403, "cross-origin requests are refused");
      return httplib::Server::HandlerResponse::Handled;
    }
    // A body over the limit is refused from its Content-Length at once (httplib would first
    // read and discard it, waiting out the read timeout when the client never sends it).
    if (req.has_header("Content-Length")) {
      const std::string length = req.get_header_value("Content-Length");
      if (length.size() > 9 || length.find_first_not_of("0123456789") != std::string::npos ||
          std::stoul("0" + length) > kMaxBody) {
        send_error(res, 413, "the request body is larger than 4 MiB");
        res.set_header("Connection", "close");
        return httplib::Server::HandlerResponse::Handled;
      }
    }
    const bool entry = req.method == "GET" && req.path == "/" && req.has_param("token") &&
                       same_token(req.get_param_value("token"), options.token);
    if (!entry && !authorized(req)) {
      send_error(res, 403,
                 "missing or wrong access token (open the URL that ramiform studio printed)");
      return httplib::Server::HandlerResponse::Handled;
    }
    return httplib::Server::HandlerResponse::Unhandled;
  }

  void routes() {
    http.set_pre_routing_handler(
        [this](const httplib::Request& req, httplib::Response& res) { return check(req, res); });
    http.Get("/", [this](const httplib::Request& req, httplib::Response& res) {
      send_asset(res, *find_asset("/index.html"));
      if (req.has_param("token")) {
        res.set_header("Set-Cookie", std::string(kCookie) + "=" + options.token +
                                         "; HttpOnly; SameSite=Strict; Path=/");
      }
    });
    http.Get("/api/info", [this](const httplib::Request&, httplib::Response& res) {
      res.set_content(info, kJson);
    });
    http.Post("/api/run", [this](const httplib::Request& req, httplib::Response& res) {
      const auto body = parse_body(req, res);
      if (!body) return;
      const auto script = body->find("script");
      if (script == body->end() || !script->is_string()) {
        return send_error(res, 400, "\"script\" must be a string");
      }
      if (script->get_ref<const std::string&>().size() > kMaxScript) {
        return send_error(res, 413, "the script is larger than 1 MiB");
      }
      std::map<std::string, std::string> params;
      if (const auto p = body->find("params"); p != body->end() && !p->is_null()) {
        if (!p->is_object() || p->size() > kMaxParams) {
          return send_error(res, 400, "\"params\" must be an object of at most 1000 values");
        }
        for (const auto& [name, value] : p->items()) {
          if (value.is_string()) {
            params[name] = value.get<std::string>();
          } else if (value.is_number()) {
            params[name] = value.dump();
          } else {
            return send_error(res, 400, "param '" + name + "' must be a string or a number");
          }
        }
      }
      bool draft = false;
      if (const auto d = body->find("draft"); d != body->end() && !d->is_null()) {
        if (!d->is_boolean()) return send_error(res, 400, "\"draft\" must be true or false");
        draft = d->get<bool>();
      }
      send_json(res, {{"run", runs->submit(script->get<std::string>(), std::move(params), draft)}});
    });
    http.Get(R"(/api/run/(r\d{1,9}))", [this](const httplib::Request& req, httplib::Response& res) {
      const auto status = runs->status(req.matches[1]);
      if (!status) return send_error(res, 404, "no run " + std::string(req.matches[1]));
      send_json(res, *status);
    });
    http.Post(R"(/api/run/(r\d{1,9})/cancel)",
              [this](const httplib::Request& req, httplib::Response& res) {
                const auto state = runs->cancel(req.matches[1]);
                if (!state) return send_error(res, 404, "no run " + std::string(req.matches[1]));
                send_json(res, {{"state", *state}});
              });
    http.Get(R"(/api/run/(r\d{1,9})/view/([oe]\d{1,9}))",
             [this](const httplib::Request& req, httplib::Response& res) {
               auto view = runs->view(req.matches[1], req.matches[2]);
               if (!view) return send_error(res, 404, "no such run or object");
               res.set_content(std::move(view->body), view->mime.c_str());
             });
    http.Get(
        R"(/files/(r\d{1,9})/(.+))", [this](const httplib::Request& req, httplib::Response& res) {
          const auto path = runs->file(req.matches[1], req.matches[2]);
          if (!path) return send_error(res, 404, "no such output");
          std::ifstream in(*path, std::ios::binary);
          std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
          std::string name = path->filename().string();
          for (char& c : name) {
            if (c == '"' || c == '\\' || static_cast<unsigned char>(c) < 0x20) c = '_';
          }
          res.set_header("Content-Disposition", "attachment; filename=\"" + name + "\"");
          res.set_content(std::move(bytes), "application/octet-stream");
        });
    http.Post("/api/lines", [this](const httplib::Request& req, httplib::Response& res) {
      lines_request(req, res);
    });
    http.Get("/api/lines/progress", [this](const httplib::Request&, httplib::Response& res) {
      const LinesProgress p = lines->progress();
      send_json(res, json{{"busy", p.busy},
                          {"stage", p.stage},
                          {"fraction", p.fraction},
                          {"seconds", p.seconds}});
    });
    // The page's other files (/index.html, /assets/...).
    http.Get(R"(/.*)", [](const httplib::Request& req, httplib::Response& res) {
      const StudioAsset* asset = find_asset(req.path);
      if (asset == nullptr) return send_error(res, 404, "not found");
      send_asset(res, *asset);
    });
    http.set_error_handler([](const httplib::Request&, httplib::Response& res) {
      if (!res.body.empty()) return;
      const std::string message = res.status == 413 ? "the request body is larger than 4 MiB"
                                  : res.status == 404
                                      ? "not found"
                                      : "bad request (HTTP " + std::to_string(res.status) + ")";
      send_error(res, res.status, message);
    });
    http.set_exception_handler(
        [](const httplib::Request&, httplib::Response& res, std::exception_ptr e) {
          std::string message = "internal error";
          try {
            if (e) std::rethrow_exception(e);
          } catch (const std::exception& x) {
            message = x.what();
          } catch (...) {
          }
          send_error(res, 500, message);
        });
  }

  void lines_request(const httplib::Request& req, httplib::Response& res) {
    const auto t0 = std::chrono::steady_clock::now();
    const auto body = parse_body(req, res);
    if (!body) return;
    const json& b = *body;
    if (!b.contains("run") || !b["run"].is_string() || !b.contains("shape") ||
        !b["shape"].is_string() || !b.contains("camera") || !b["camera"].is_object()) {
      return send_error(res, 400,
                        "\"run\" and \"shape\" (strings) and \"camera\" (an object) are needed");
    }
    const json& c = b["camera"];
    PageCamera camera;
    for (const auto& [key, slot] :
         {std::pair{"eye", &camera.eye}, std::pair{"target", &camera.target},
          std::pair{"up", &camera.up}}) {
      if (!c.contains(key)) continue;
      const auto v = vec3(c[key]);
      if (!v) return send_error(res, 400, std::string("camera.") + key + " must be [x, y, z]");
      *slot = *v;
    }
    const auto number = [&](const char* key, double fallback, double& out) {
      if (!c.contains(key)) return (out = fallback, true);
      if (!c[key].is_number()) return false;
      out = c[key].get<double>();
      return true;
    };
    double fov = 0, width = 0, height = 0;
    if (!number("fov", 30, fov) || !number("width", 800, width) || !number("height", 600, height) ||
        !(width >= 16 && width <= 8192 && height >= 16 && height <= 8192)) {
      return send_error(res, 400,
                        "camera.fov, .width and .height must be numbers (16..8192 pixels)");
    }
    camera.fov_deg = fov;
    camera.width = static_cast<int>(width);
    camera.height = static_cast<int>(height);
    std::vector<std::string> kinds = {"silhouette", "suggestive", "feature"};
    if (b.contains("lines")) {
      if (!b["lines"].is_array() || b["lines"].size() > 8) {
        return send_error(res, 400, "\"lines\" must be a list of line kinds");
      }
      kinds.clear();
      for (const json& k : b["lines"]) {
        if (!k.is_string()) return send_error(res, 400, "\"lines\" must be a list of line kinds");
        kinds.push_back(k.get<std::string>());
      }
    }
    double count = 10000;
    if (b.contains("count")) {
      if (!b["count"].is_number()) return send_error(res, 400, "\"count\" must be a number");
      count = b["count"].get<double>();
      if (!(count >= 1 && count <= static_cast<double>(LineViews::kMaxCount))) {
        return send_error(res, 400,
                          "\"count\" must be in 1.." + std::to_string(LineViews::kMaxCount));
      }
    }
    bool surfels = false;
    if (b.contains("visibility")) {
      const json& v = b["visibility"];
      if (!v.is_string() || (v != "rays" && v != "surfels")) {
        return send_error(res, 400, "\"visibility\" must be \"rays\" or \"surfels\"");
      }
      surfels = v == "surfels";
    }
    const std::string run = b["run"].get<std::string>();
    const std::string shape = b["shape"].get<std::string>();
    const FieldPtr field = runs->shape(run, shape);
    if (!field) {
      return send_error(res, 404,
                        "no shape '" + shape + "' in run '" + run +
                            "' (only the newest finished runs keep their shapes)");
    }
    try {
      std::string svg =
          lines->draw(run, shape, field, camera, kinds, static_cast<std::size_t>(count), surfels);
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      res.set_header("X-Ramiform-Seconds", format_number(seconds));
      res.set_content(std::move(svg), "image/svg+xml");
    } catch (const InvalidArgument& e) {
      send_error(res, 400, e.what());
    } catch (const InputError& e) {
      send_error(res, 400, e.what());
    }
  }
};

StudioServer::StudioServer(StudioOptions options) : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.options = std::move(options);
  if (s.options.token.empty()) s.options.token = random_token();
  std::error_code ec;
  fs::create_directories(s.options.out_dir / "runs", ec);
  fs::create_directories(s.options.out_dir / "cache", ec);
  if (ec || !fs::is_directory(s.options.out_dir, ec)) {
    throw InvalidArgument("cannot create the output directory '" + s.options.out_dir.string() +
                          "'");
  }
  RunSettings settings;
  settings.out_dir = fs::canonical(s.options.out_dir);
  if (s.options.script_path.empty()) {
    s.script = s.options.demo_script;
    s.script_name = "studio.rf";
    settings.input_dir = settings.out_dir;
  } else {
    s.script = read_text(s.options.script_path);
    s.script_name = fs::path(s.options.script_path).filename().string();
    const fs::path dir = fs::path(s.options.script_path).parent_path();
    settings.input_dir = dir.empty() ? fs::path(".") : dir;
  }
  settings.script_name = s.script_name;
  settings.timeout_seconds = s.options.run_timeout;
  settings.max_memory = s.options.max_memory;
  settings.threads = s.options.threads;
  json commands = json::array();
  for (const CommandInfo& c : ScriptSession::commands()) {
    commands.push_back({{"name", c.name},
                        {"synopsis", c.synopsis},
                        {"options", c.options},
                        {"description", c.description}});
  }
  s.info = json{{"version", s.options.version},
                {"script", s.script},
                {"script_name", s.script_name},
                {"page_built", studio_page_built()},
                {"commands", commands}}
               .dump(-1, ' ', false, json::error_handler_t::replace);
  s.lines = std::make_unique<LineViews>(settings.out_dir / "cache", s.options.threads,
                                        s.options.max_memory);
  s.runs = std::make_unique<RunManager>(std::move(settings));
  s.http.new_task_queue = [] { return new httplib::ThreadPool(kHttpThreads); };
  s.http.set_payload_max_length(kMaxBody);
  s.http.set_read_timeout(kSocketTimeoutSeconds, 0);
  s.http.set_write_timeout(kSocketTimeoutSeconds, 0);
  s.http.set_keep_alive_timeout(kSocketTimeoutSeconds);
  s.routes();
}

StudioServer::~StudioServer() { stop(); }

int StudioServer::start() {
  Impl& s = *impl_;
  const int port =
      s.options.port == 0
          ? s.http.bind_to_any_port(s.options.listen)
          : (s.http.bind_to_port(s.options.listen, s.options.port) ? s.options.port : -1);
  if (port <= 0) {
    throw Failure("cannot listen on " + s.options.listen + ":" + std::to_string(s.options.port));
  }
  s.port = port;
  s.thread = std::thread([&s] { s.http.listen_after_bind(); });
  // Serving before returning, so that stop() finds the server running.
  while (!s.http.is_running()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  return port;
}

void StudioServer::stop() {
  Impl& s = *impl_;
  s.http.stop();
  if (s.thread.joinable()) s.thread.join();
  s.runs.reset();
}

const std::string& StudioServer::token() const { return impl_->options.token; }

std::string StudioServer::url() const {
  const std::string& l = impl_->options.listen;
  const bool any = l == "127.0.0.1" || l == "0.0.0.0" || l == "::" || l == "localhost";
  const std::string host =
      any ? "127.0.0.1" : (l.find(':') != std::string::npos ? "[" + l + "]" : l);
  return "http://" + host + ":" + std::to_string(impl_->port.load()) +
         "/?token=" + impl_->options.token;
}

}  // namespace ramiform::studio
