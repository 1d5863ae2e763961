// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "studio/line_views.h"

#include <fstream>
#include <future>
#include <iterator>
#include <system_error>

#include "ramiform/core/context.h"
#include "ramiform/core/errors.h"
#include "ramiform/io/drawing_io.h"
#include "ramiform/lines/lines.h"
#include "ramiform/particles/surface_particles.h"

namespace ramiform::studio {

namespace fs = std::filesystem;

struct LineViews::Entry {
  std::mutex m;  // held while the particles are spread, so that they are spread once
  bool ready = false;
  FieldPtr field;
  ParticleSystem particles;
  std::vector<Polyline> features;  // view-independent: found once
  std::unique_ptr<ParticleLookup> lookup;  // the particles' k-d tree and surfel radii, made once
};

Vec3 from_page(const std::array<double, 3>& p) { return {p[0], -p[2], p[1]}; }

LineViews::LineViews(fs::path scratch, int threads, std::uint64_t max_memory)
    : scratch_(std::move(scratch)), threads_(threads), max_memory_(max_memory) {}

LinesProgress LineViews::progress() const {
  std::lock_guard lock(progress_mutex_);
  LinesProgress p = progress_;
  if (p.busy) {
    p.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - progress_start_).count();
  }
  return p;
}

void LineViews::report(std::uint64_t ticket, const std::string& stage, double fraction) {
  std::lock_guard lock(progress_mutex_);
  if (ticket != newest_) return;
  progress_.stage = stage;
  progress_.fraction = fraction;
}

std::shared_ptr<LineViews::Entry> LineViews::entry(const std::string& key) {
  std::lock_guard lock(mutex_);
  for (auto it = cache_.begin(); it != cache_.end(); ++it) {
    if (it->first == key) {
      cache_.splice(cache_.begin(), cache_, it);
      return cache_.front().second;
    }
  }
  cache_.emplace_front(key, std::make_shared<Entry>());
  if (cache_.size() > kMaxCached) cache_.pop_back();
  return cache_.front().second;
}

std::string LineViews::draw(const std::string& run, const std::string& shape, const FieldPtr& field,
                            const PageCamera& page, const std::vector<std::string>& kinds,
                            std::size_t count, bool surfels) {
  if (count < 1 || count > kMaxCount) {
    throw InvalidArgument("count must be in 1.." + std::to_string(kMaxCount));
  }
  if (page.width < 16 || page.width > 8192 || page.height < 16 || page.height > 8192) {
    throw InvalidArgument("camera width and height must be in 16..8192");
  }
  LineOptions options;  // `ramiform draw`'s defaults, hidden lines by rays
  options.visibility = surfels ? Visibility::kSurfels : Visibility::kRays;
  select_line_kinds(options, kinds);
  validate(options);
  Camera camera;
  camera.eye = from_page(page.eye);
  camera.target = from_page(page.target);
  camera.up = from_page(page.up);
  camera.fov_deg = page.fov_deg;
  camera.aspect = static_cast<double>(page.width) / page.height;
  validate(camera);

  return on_worker([&] { return render(run, shape, field, page, options, camera, count); });
}

LineViews::~LineViews() {
  {
    std::lock_guard lock(queue_mutex_);
    stopping_ = true;
  }
  queue_cv_.notify_all();
  if (worker_.joinable()) worker_.join();
}

std::string LineViews::on_worker(const std::function<std::string()>& work) {
  std::packaged_task<std::string()> task(work);
  std::future<std::string> result = task.get_future();
  {
    std::lock_guard lock(queue_mutex_);
    if (!worker_.joinable()) worker_ = std::thread([this] { serve(); });
    queue_.push_back(std::move(task));
  }
  queue_cv_.notify_one();
  return result.get();  // the drawing's exception, if it threw
}

void LineViews::serve() {
  for (;;) {
    std::packaged_task<std::string()> task;
    {
      std::unique_lock lock(queue_mutex_);
      queue_cv_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
      if (queue_.empty()) return;  // stopping, every drawing asked for done
      task = std::move(queue_.front());
      queue_.pop_front();
    }
    task();
  }
}

std::string LineViews::render(const std::string& run, const std::string& shape,
                              const FieldPtr& field, const PageCamera& page,
                              const LineOptions& options, const Camera& camera, std::size_t count) {
  std::uint64_t ticket = 0;
  {
    std::lock_guard lock(progress_mutex_);
    ticket = ++newest_;
    progress_ = {true, "lines", 0.0, 0.0};
    progress_start_ = std::chrono::steady_clock::now();
  }
  // The newest drawing's progress ends with it, however it ends.
  struct Finish {
    LineViews& views;
    std::uint64_t ticket;
    ~Finish() {
      std::lock_guard lock(views.progress_mutex_);
      if (views.newest_ == ticket) views.progress_.busy = false;
    }
  } finish{*this, ticket};
  Context ctx(threads_);
  ctx.set_max_memory(max_memory_);
  ctx.set_progress([this, ticket](const std::string& stage, double fraction) {
    report(ticket, stage, fraction);
  });
  const std::shared_ptr<Entry> e = entry(run + "\n" + shape + "\n" + std::to_string(count));
  std::lock_guard lock(e->m);
  if (!e->ready) {
    ParticleOptions po;  // as `draw SHAPE FILE count=N`
    po.count = count;
    e->field = field;
    e->particles = spread_particles(*field, po, field_cells(*field), {}, nullptr, &ctx);
    if (e->particles.particles.empty()) {
      throw InvalidArgument("no particles reached the surface of '" + shape + "'");
    }
    LineOptions all = options;
    all.features = true;
    report(ticket, "lines: feature lines", 0.0);
    e->features = feature_lines(*field, e->particles, all, nullptr, &ctx);
    e->lookup = std::make_unique<ParticleLookup>(e->particles);
    e->ready = true;
  }
  report(ticket, "lines: this camera", 0.0);
  const LineDrawing drawing = draw_lines(*e->field, e->particles, camera, options, &e->features,
                                         nullptr, &ctx, e->lookup.get());
  DrawingStyle style;
  style.width = page.width;
  style.height = page.height;
  fs::path path;
  {
    std::lock_guard cache_lock(mutex_);
    path = scratch_ / ("lines-" + std::to_string(next_file_++) + ".svg");
  }
  write_drawing_svg(path.string(), drawing, style);
  std::ifstream in(path, std::ios::binary);
  std::string svg((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::error_code ec;
  fs::remove(path, ec);
  return svg;
}

}  // namespace ramiform::studio
