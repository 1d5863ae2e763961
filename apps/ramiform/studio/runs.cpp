// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "studio/runs.h"

#include <algorithm>
#include <fstream>
#include <iterator>
#include <new>
#include <set>
#include <sstream>
#include <system_error>

#include "ramiform/core/errors.h"
#include "ramiform/core/numbers.h"
#include "ramiform/io/mesh_io.h"
#include "ramiform/io/particles_io.h"
#include "ramiform/io/points_io.h"
#include "ramiform/io/skeleton_io.h"
#include "ramiform/mesh/checks.h"
#include "ramiform/mesh/normals.h"
#include "ramiform/script/script.h"
#include "studio/util.h"

namespace ramiform::studio {

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

namespace {

/// Most points a points view holds (the rest are counted in "total").
constexpr std::size_t kMaxViewPoints = 200'000;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// The library's +Z up as the page's +Y up: the rotation write_mesh applies to a .glb
// ((x, y, z) -> (x, z, -y), io/mesh_io.h UpAxis::kY).
json y_up(const Vec3& v) { return json::array({v.x(), v.z(), -v.y()}); }

std::string read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// "tree.lod0.ply" -> "tree".
std::string stem_of(const std::string& path) {
  std::string name = fs::path(path).filename().string();
  return name.substr(0, name.find('.'));
}

}  // namespace

struct RunManager::Run {
  struct Object {
    std::string id;
    std::string mime;       // of the view
    fs::path view_file;     // the view's bytes are this file's, or
    std::string view_body;  // these
  };

  std::string id;
  fs::path dir;
  std::string script;
  std::map<std::string, std::string> params;
  bool draft = false;  // ScriptOptions::draft
  Context ctx;

  mutable std::mutex m;  // guards everything below
  std::string state = "running";
  std::string stage = "queued";
  double fraction = 0;
  bool started = false;
  Clock::time_point start;
  double seconds = 0;
  bool committed = false;
  bool timed_out = false;
  json error = nullptr;
  json param_list = json::array();
  json log = json::array();
  json objects = json::array();
  json shapes = json::array();
  json outputs = json::array();
  std::vector<Object> views;
  // Meshes shown before the run ends (ScriptOptions::on_mesh): their entries in the status and
  // their views ("e0", "e1", ...); the views are freed when the next run starts.
  json early = json::array();
  std::vector<Object> early_views;
  std::map<std::string, FieldPtr> fields;
};

namespace {

// Which command of the script wrote an output, at which line (0: the server's preview mesh).
struct Writer {
  std::string command;
  std::size_t line = 0;
  std::map<std::string, double> facts;  // CommandResult::facts
  std::string shape;                    // CommandResult::shape
};

// The objects of the committed outputs, grouped by the command line that wrote them.
void add_objects(RunManager::Run& run, const std::vector<std::string>& written,
                 const std::map<std::string, Writer>& writers, const fs::path& cache) {
  std::vector<std::pair<Writer, std::vector<std::string>>> groups;
  for (const std::string& path : written) {
    const auto it = writers.find(path);
    if (it == writers.end()) continue;
    const Writer& w = it->second;
    if (groups.empty() || groups.back().first.line != w.line ||
        groups.back().first.command != w.command) {
      groups.push_back({w, {}});
    }
    groups.back().second.push_back(path);
  }
  for (const auto& [writer, files] : groups) {
    RunManager::Run::Object view;
    view.id = "o" + std::to_string(run.views.size());
    json object = {{"id", view.id},
                   {"name", stem_of(files.front())},
                   {"view", "/api/run/" + run.id + "/view/" + view.id},
                   {"preview", writer.line == 0}};
    const auto rel = [&](const std::string& p) {
      return fs::path(p).lexically_relative(run.dir).string();
    };
    try {
      if (writer.command == "save_mesh") {
        std::string glb, other;
        for (const std::string& f : files) {
          std::string& slot = lower_ext(f) == ".glb" ? glb : other;
          if (slot.empty()) slot = f;  // the finest level of detail comes first
        }
        // The mesh's facts as save_mesh reported them; a .ply/.obj/.off beside the glb is read
        // back and checked instead.
        json stats = {{"watertight", nullptr}};
        if (writer.facts.count("triangles") != 0) {
          const auto count = [&](const char* key) {
            return static_cast<std::size_t>(writer.facts.at(key));
          };
          stats = {{"vertices", count("vertices")},
                   {"triangles", count("triangles")},
                   {"watertight", writer.facts.at("watertight") != 0},
                   {"boundary_edges", count("boundary_edges")}};
        }
        if (!other.empty()) {
          TriMesh mesh = read_mesh(other);
          const MeshReport report = check_mesh(mesh);
          stats = {{"vertices", mesh.vertex_count()},
                   {"triangles", mesh.triangle_count()},
                   {"watertight", report.watertight && report.oriented && report.manifold},
                   {"boundary_edges", report.boundary_edges}};
          if (glb.empty()) {
            if (mesh.normals.empty()) set_normals_from_faces(mesh);
            mesh.uvs.clear();
            mesh.tangents.clear();
            mesh.welded.clear();
            view.view_file = cache / (view.id + ".glb");
            write_mesh(mesh, view.view_file.string());
          }
        }
        if (!glb.empty()) view.view_file = glb;
        view.mime = "model/gltf-binary";
        object["kind"] = "mesh";
        object["shape"] = writer.shape;
        object["line"] = writer.line;
        object["file"] = rel(glb.empty() ? other : glb);
        object["stats"] = stats;
      } else if (writer.command == "save_skeleton") {
        const Skeleton sk = read_skeleton(files.front());
        json nodes = json::array(), radii = json::array(), edges = json::array();
        for (const SkeletonNode& n : sk.nodes) {
          nodes.push_back(y_up(n.position));
          radii.push_back(n.radius);
        }
        for (const auto& e : sk.edges) edges.push_back({e[0], e[1]});
        view.view_body = json{{"nodes", nodes}, {"edges", edges}, {"radii", radii}}.dump();
        view.mime = "application/json";
        object["kind"] = "skeleton";
        object["file"] = rel(files.front());
        object["stats"] = {{"nodes", sk.node_count()}, {"edges", sk.edge_count()}};
      } else if (writer.command == "save_point_set" || writer.command == "particles") {
        PointSet points;
        if (writer.command == "particles") {
          const ParticleSystem system = read_particles(files.front());
          for (const SurfaceParticle& p : system.particles) {
            points.positions.push_back(p.position);
            points.normals.push_back(p.normal);
          }
        } else {
          points = read_points(files.front());
        }
        const std::size_t shown = std::min(points.size(), kMaxViewPoints);
        json positions = json::array(), normals = json::array();
        for (std::size_t i = 0; i < shown; ++i) {
          positions.push_back(y_up(points.positions[i]));
          if (points.has_normals()) normals.push_back(y_up(points.normals[i]));
        }
        view.view_body = json{
            {"points", positions},
            {"normals", points.has_normals() ? normals : json(nullptr)},
            {"total",
             points.size()}}.dump();
        view.mime = "application/json";
        object["kind"] = "points";
        object["file"] = rel(files.front());
        object["stats"] = {{"points", points.size()}};
      } else if (writer.command == "draw") {
        const std::string& f = files.front();
        const std::string ext = lower_ext(f);
        if (ext != ".svg" && ext != ".png") continue;
        view.view_file = f;
        view.mime = ext == ".svg" ? "image/svg+xml" : "image/png";
        object["kind"] = "drawing";
        object["file"] = rel(f);
        std::error_code ec;
        object["stats"] = {{"bytes", fs::file_size(f, ec)}};
      } else {
        continue;
      }
    } catch (const std::exception&) {
      continue;  // an output the viewer cannot read is still listed for download
    }
    run.objects.push_back(std::move(object));
    run.views.push_back(std::move(view));
  }
}

json error_json(const std::string& message, std::size_t line = 0, std::size_t column = 0) {
  return {{"message", message},
          {"line", line > 0 ? json(line) : json(nullptr)},
          {"column", column > 0 ? json(column) : json(nullptr)}};
}

}  // namespace

RunManager::RunManager(RunSettings settings) : settings_(std::move(settings)) {
  std::error_code ec;
  // Run numbers go on from the runs an earlier server left in OUT/runs.
  for (const auto& entry : fs::directory_iterator(settings_.out_dir / "runs", ec)) {
    const std::string name = entry.path().filename().string();
    if (name.size() < 2 || name[0] != 'r') continue;
    int n = 0;
    if (parse_int(name.substr(1), n)) next_number_ = std::max(next_number_, n + 1);
  }
  worker_ = std::thread([this] { work(); });
  watchdog_ = std::thread([this] { watch(); });
}

RunManager::~RunManager() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
    if (pending_) pending_->ctx.cancel();
    if (current_) current_->ctx.cancel();
  }
  wake_.notify_all();
  worker_.join();
  watchdog_.join();
}

std::string RunManager::submit(std::string script, std::map<std::string, std::string> params,
                               bool draft) {
  auto run = std::make_shared<Run>();
  run->script = std::move(script);
  run->params = std::move(params);
  run->draft = draft;
  std::string id;
  std::vector<fs::path> forgotten_drafts;
  {
    std::lock_guard lock(mutex_);
    id = "r" + std::to_string(next_number_++);
    run->id = id;
    run->dir = settings_.out_dir / "runs" / id;
    if (pending_) {
      pending_->ctx.cancel();
      std::lock_guard run_lock(pending_->m);
      pending_->state = "cancelled";
    }
    if (current_) current_->ctx.cancel();  // the latest run wins
    pending_ = run;
    runs_[id] = run;
    order_.push_back(id);
    while (order_.size() > kMaxRuns) {
      const auto old = runs_.find(order_.front());
      if (old != runs_.end()) {
        // A draft no longer running: its directory goes too.
        if (old->second->draft && old->second != current_) {
          forgotten_drafts.push_back(old->second->dir);
        }
        runs_.erase(old);
      }
      order_.pop_front();
    }
  }
  wake_.notify_all();
  // Forgotten and not running: nothing writes there any more.
  for (const fs::path& dir : forgotten_drafts) {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  return id;
}

void RunManager::work() {
  for (;;) {
    std::shared_ptr<Run> run;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [this] { return stopping_ || pending_ != nullptr; });
      if (stopping_) return;
      run = std::move(pending_);
      pending_ = nullptr;
      current_ = run;
    }
    // Early meshes are for the page while their run goes on (and just after): a new run frees
    // the earlier runs' (their entries stay listed; their views answer 404).
    std::vector<fs::path> early_files;
    {
      std::lock_guard lock(mutex_);
      for (const auto& [id, other] : runs_) {
        if (other == run) continue;
        std::lock_guard run_lock(other->m);
        for (const Run::Object& o : other->early_views) early_files.push_back(o.view_file);
        other->early_views.clear();
      }
    }
    for (const fs::path& f : early_files) {
      std::error_code ec;
      fs::remove(f, ec);
    }
    execute(*run);
    std::lock_guard lock(mutex_);
    current_ = nullptr;
    // Only the newest finished runs keep their shapes (for line drawings).
    std::size_t kept = 0;
    for (auto it = order_.rbegin(); it != order_.rend(); ++it) {
      const auto found = runs_.find(*it);
      if (found == runs_.end()) continue;
      Run& r = *found->second;
      std::lock_guard run_lock(r.m);
      if (r.fields.empty()) continue;
      if (++kept > kMaxRunsWithShapes) r.fields.clear();
    }
  }
}

void RunManager::watch() {
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    wake_.wait_for(lock, std::chrono::milliseconds(100));
    if (!current_) continue;
    std::lock_guard run_lock(current_->m);
    if (current_->started && !current_->timed_out && !current_->committed &&
        seconds_since(current_->start) > settings_.timeout_seconds) {
      current_->timed_out = true;
      current_->ctx.cancel();
    }
  }
}

void RunManager::execute(Run& run) {
  {
    std::lock_guard lock(run.m);
    if (run.ctx.is_cancelled()) {
      run.state = "cancelled";
      return;
    }
    run.started = true;
    run.start = Clock::now();
    run.stage = "starting";
  }
  run.ctx.set_threads(settings_.threads);
  run.ctx.set_max_memory(settings_.max_memory);
  run.ctx.set_progress([&run](const std::string& stage, double fraction) {
    std::lock_guard lock(run.m);
    run.stage = stage;
    run.fraction = fraction;
  });
  const std::string& file = settings_.script_name;
  std::map<std::string, Writer> writers;
  try {
    std::error_code ec;
    fs::create_directories(run.dir, ec);
    if (ec) throw Failure("cannot create '" + run.dir.string() + "': " + ec.message());
    ScriptOptions options;
    options.out_dir = run.dir.string();
    options.input_dir = settings_.input_dir.string();
    options.params = run.params;
    options.draft = run.draft;
    // A full run shows each mesh as soon as it is polygonized: bark UVs and the files can take
    // as long again (docs/studio_api.md, "early"). Drafts are quick enough without.
    std::size_t current_line = 0;
    const fs::path early_dir = settings_.out_dir / "cache" / run.id;
    if (!run.draft) {
      options.on_mesh = [&](const std::string& shape, const TriMesh& polygonized) {
        TriMesh mesh;
        mesh.positions = polygonized.positions;
        mesh.triangles = polygonized.triangles;
        set_normals_from_faces(mesh);
        std::size_t number = 0;
        {
          std::lock_guard lock(run.m);
          number = run.early_views.size();
        }
        Run::Object view;
        view.id = "e" + std::to_string(number);
        view.mime = "model/gltf-binary";
        view.view_file = early_dir / (view.id + ".glb");
        std::error_code dir_ec;
        fs::create_directories(early_dir, dir_ec);
        try {
          write_mesh(mesh, view.view_file.string());
        } catch (const Failure&) {
          return;  // no early view (e.g. the disk is full); the run goes on to its own files
        }
        std::lock_guard lock(run.m);
        run.early.push_back(
            {{"id", view.id},
             {"kind", "mesh"},
             {"shape", shape},
             {"line", current_line},
             {"view", "/api/run/" + run.id + "/view/" + view.id},
             {"stats", {{"vertices", mesh.vertex_count()}, {"triangles", mesh.triangle_count()}}}});
        run.early_views.push_back(std::move(view));
      };
    }
    ScriptSession session(options, &run.ctx);
    const auto note_outputs = [&](const CommandResult& r, std::size_t line) {
      for (const std::string& p : session.staged_outputs())
        writers.emplace(p, Writer{r.command, line, r.facts, r.shape});
    };
    const std::string_view text = run.script;
    const std::size_t lines =
        static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')) + 1;
    std::size_t line = 1;
    for (std::size_t at = 0; at <= text.size(); ++line) {
      std::size_t end = text.find('\n', at);
      if (end == std::string_view::npos) end = text.size();
      check_cancel(&run.ctx);
      {
        std::lock_guard lock(run.m);
        run.stage = "line " + std::to_string(line);
        run.fraction = static_cast<double>(line - 1) / static_cast<double>(lines);
      }
      current_line = line;
      const auto t0 = Clock::now();
      const CommandResult r = session.execute_line(text.substr(at, end - at), file, line);
      const double seconds = seconds_since(t0);
      note_outputs(r, line);
      if (!r.command.empty()) {
        std::lock_guard lock(run.m);
        run.log.push_back(
            {{"line", line}, {"command", r.command}, {"message", r.message}, {"seconds", seconds}});
      }
      at = end + 1;
    }
    for (const auto& [name, value] : run.params) {
      const auto& declared = session.params();
      if (std::none_of(declared.begin(), declared.end(),
                       [&](const ScriptParam& p) { return p.name == name; })) {
        throw InputError(file, 0, "params: the script declares no parameter '" + name + "'");
      }
    }
    // No mesh saved: a preview of the shape defined last, meshed as save_mesh does (to the
    // tolerance when the shape has a skeleton, else marching cubes).
    const bool has_mesh = std::any_of(writers.begin(), writers.end(), [](const auto& w) {
      return w.second.command == "save_mesh";
    });
    const std::vector<std::string> shapes = session.shape_names();
    if (!has_mesh && !shapes.empty()) {
      const std::string name = shapes.back();
      const std::string files = " " + name + ".preview.glb";
      current_line = 0;
      {
        std::lock_guard lock(run.m);
        run.stage = "preview mesh";
      }
      CommandResult preview;
      try {
        preview =
            session.execute_line("save_mesh " + name + files + " method=tets", "<preview>", 1);
      } catch (const InputError&) {
        try {
          preview = session.execute_line("save_mesh " + name + files, "<preview>", 1);
        } catch (const InputError& e) {
          std::lock_guard lock(run.m);
          run.log.push_back(
              {{"line", nullptr}, {"command", "preview"}, {"message", e.what()}, {"seconds", 0}});
        }
      }
      preview.command = "save_mesh";
      note_outputs(preview, 0);
    }
    std::vector<std::string> written;
    {
      std::lock_guard lock(run.m);
      check_cancel(&run.ctx);
      written = session.commit();
      run.committed = true;
      for (const ScriptParam& p : session.params()) {
        json entry = {{"name", p.name}, {"value", p.value}};
        if (p.min) entry["min"] = *p.min;
        if (p.max) entry["max"] = *p.max;
        if (p.step) entry["step"] = *p.step;
        run.param_list.push_back(std::move(entry));
      }
      for (const std::string& s : shapes) {
        run.shapes.push_back(s);
        run.fields[s] = session.shape(s);
      }
      run.stage = "objects";
    }
    Run scratch;  // objects and outputs are made outside the lock, then moved in
    scratch.id = run.id;
    scratch.dir = run.dir;
    const fs::path cache = settings_.out_dir / "cache" / run.id;
    fs::create_directories(cache, ec);
    add_objects(scratch, written, writers, cache);
    for (const std::string& p : written) {
      const std::string rel = fs::path(p).lexically_relative(run.dir).string();
      scratch.outputs.push_back({{"path", rel},
                                 {"bytes", fs::file_size(p, ec)},
                                 {"url", "/files/" + run.id + "/" + url_encode_path(rel)}});
    }
    std::lock_guard lock(run.m);
    run.objects = std::move(scratch.objects);
    run.views = std::move(scratch.views);
    run.outputs = std::move(scratch.outputs);
    run.state = "done";
  } catch (const Cancelled&) {
    std::lock_guard lock(run.m);
    if (run.timed_out) {
      run.state = "failed";
      run.error = error_json("the run took longer than --run-timeout " +
                             format_number(settings_.timeout_seconds) + " s and was stopped");
    } else {
      run.state = "cancelled";
    }
  } catch (const InputError& e) {
    std::lock_guard lock(run.m);
    run.state = "failed";
    if (e.file() == file && e.line() > 0) {
      run.error = error_json(e.what(), e.line(), e.column());
    } else {
      run.error = error_json(e.what());
    }
  } catch (const std::bad_alloc&) {
    std::lock_guard lock(run.m);
    run.state = "failed";
    run.error = error_json("out of memory");
  } catch (const std::exception& e) {
    std::lock_guard lock(run.m);
    run.state = "failed";
    run.error = error_json(e.what());
  }
  std::lock_guard lock(run.m);
  run.seconds = seconds_since(run.start);
  run.ctx.set_progress(nullptr);
}

std::shared_ptr<RunManager::Run> RunManager::find(const std::string& id) const {
  std::lock_guard lock(mutex_);
  const auto it = runs_.find(id);
  return it == runs_.end() ? nullptr : it->second;
}

std::optional<json> RunManager::status(const std::string& id) const {
  const std::shared_ptr<Run> run = find(id);
  if (!run) return std::nullopt;
  std::lock_guard lock(run->m);
  const bool running = run->state == "running";
  return json{{"run", run->id},
              {"draft", run->draft},
              {"state", run->state},
              {"progress", {{"stage", run->stage}, {"fraction", run->fraction}}},
              {"seconds", running && run->started ? seconds_since(run->start) : run->seconds},
              {"error", run->error},
              {"params", run->param_list},
              {"log", run->log},
              {"early", run->early},
              {"objects", run->objects},
              {"shapes", run->shapes},
              {"outputs", run->outputs}};
}

std::optional<std::string> RunManager::cancel(const std::string& id) {
  const std::shared_ptr<Run> run = find(id);
  if (!run) return std::nullopt;
  std::lock_guard lock(run->m);
  if (run->state != "running") return run->state;
  if (run->committed) return std::string("done");  // past the last point it could stop
  run->ctx.cancel();
  return std::string("cancelled");
}

std::optional<ViewData> RunManager::view(const std::string& id, const std::string& object) const {
  const std::shared_ptr<Run> run = find(id);
  if (!run) return std::nullopt;
  Run::Object found;
  {
    std::lock_guard lock(run->m);
    const auto is_it = [&](const Run::Object& o) { return o.id == object; };
    const auto it = std::find_if(run->views.begin(), run->views.end(), is_it);
    const auto early = std::find_if(run->early_views.begin(), run->early_views.end(), is_it);
    if (it != run->views.end()) {
      found = *it;
    } else if (early != run->early_views.end()) {
      found = *early;
    } else {
      return std::nullopt;
    }
  }
  if (found.view_file.empty()) return ViewData{found.mime, std::move(found.view_body)};
  std::error_code ec;
  if (!fs::is_regular_file(found.view_file, ec)) return std::nullopt;
  return ViewData{found.mime, read_bytes(found.view_file)};
}

std::optional<fs::path> RunManager::file(const std::string& id, const std::string& path) const {
  const std::shared_ptr<Run> run = find(id);
  if (!run) return std::nullopt;
  const fs::path& dir = run->dir;
  std::error_code ec;
  const fs::path base = fs::canonical(dir, ec);
  if (ec) return std::nullopt;
  const fs::path target = fs::weakly_canonical(base / fs::path(path).relative_path(), ec);
  if (ec || !inside(target, base) || !fs::is_regular_file(target, ec)) return std::nullopt;
  return target;
}

FieldPtr RunManager::shape(const std::string& id, const std::string& name) const {
  const std::shared_ptr<Run> run = find(id);
  if (!run) return nullptr;
  std::lock_guard lock(run->m);
  const auto it = run->fields.find(name);
  return it == run->fields.end() ? nullptr : it->second;
}

}  // namespace ramiform::studio
