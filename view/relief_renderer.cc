#include "view/relief_renderer.h"

#include <fstream>
#include <sstream>

#include "log/log.h"
#include "runtime/process_runtime.h"
#include "terrain/ground_level.h"

namespace dt {

ReliefRenderer::ReliefRenderer(std::filesystem::path png_path)
    : png_path_(std::move(png_path)), thread_([this] { Run(); }) {}

ReliefRenderer::~ReliefRenderer() {
  {
    std::lock_guard lock(mu_);
    stop_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

bool ReliefRenderer::Offer(const Terrain& terrain) {
  std::lock_guard lock(mu_);
  if (busy_) return false;
  busy_ = true;
  // A large world is drawn from a level of detail at the picture's resolution, taken here from
  // the posts it keeps: the whole grid is never copied or drawn (docs/real-ground.md "Large
  // worlds"). Blade work is in the posts kept; its post indices are the fine grid's.
  const bool coarse = CoarseStride(terrain.ground()) > 1;
  Job job{CoarseGround(terrain.ground()), {}};
  for (const Feature* f : terrain.FeaturesById()) {
    if (coarse && f->type() == FeatureType::kEarthMove) continue;
    job.features.emplace_back(f->id(), f->params());
  }
  todo_.emplace(std::move(job));
  wake_.notify_all();
  return true;
}

std::optional<std::string> ReliefRenderer::Take() {
  std::lock_guard lock(mu_);
  std::optional<std::string> out = std::move(done_);
  done_.reset();
  return out;
}

void ReliefRenderer::Run() {
  for (;;) {
    std::optional<Job> job;
    {
      std::unique_lock lock(mu_);
      wake_.wait(lock, [this] { return stop_ || todo_.has_value(); });
      if (stop_) return;
      job = std::move(todo_);
      todo_.reset();
    }
    // The same features in the same order place alike (docs/protocol.md "Materialisation").
    Terrain terrain(std::move(job->ground));
    for (const auto& [id, params] : job->features) (void)terrain.Add(id, params);
    // The renderer's one OSMesa context lives on this thread only (RenderMapPng's own).
    std::optional<std::string> bytes;
    if (Status s = RenderMapPng(terrain, std::vector<VehicleSprite>{}, png_path_.string()); !s) {
      DT_LOG_WARN("relief: {}", s.error().message);
    } else {
      std::ifstream in(png_path_, std::ios::binary);
      std::ostringstream b;
      b << in.rdbuf();
      bytes = b.str();
    }
    std::lock_guard lock(mu_);
    busy_ = false;
    if (bytes) done_ = std::move(bytes);
  }
}

}  // namespace dt
