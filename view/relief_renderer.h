// ReliefRenderer: renders the view's relief image (render/, OSMesa on the CPU) on a thread of its
// own, so a render never holds the view's loop (PDUs, silence, deltas) for its duration.
#pragma once

#include <condition_variable>
#include <filesystem>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "terrain/terrain.h"

namespace dt {

class ReliefRenderer {
 public:
  // Writes each render to `png_path` (and keeps its bytes).
  explicit ReliefRenderer(std::filesystem::path png_path);
  ~ReliefRenderer();
  ReliefRenderer(const ReliefRenderer&) = delete;
  ReliefRenderer& operator=(const ReliefRenderer&) = delete;

  // Starts rendering `terrain` (its ground, at most kReliefMaxPostsPerSide posts a side of it
  // (CoarseGround), and its placed features, copied) unless a render is under way; false if one
  // is.
  bool Offer(const Terrain& terrain);
  // The PNG bytes of a render finished since the last call, if any.
  std::optional<std::string> Take();

 private:
  void Run();

  std::filesystem::path png_path_;
  std::mutex mu_;
  std::condition_variable wake_;
  struct Job {
    HeightGrid ground;
    std::vector<std::pair<FeatureId, FeatureParams>> features;  // in ID order, as placed
  };
  std::optional<Job> todo_;
  bool busy_ = false;
  bool stop_ = false;
  std::optional<std::string> done_;
  std::thread thread_;
};

}  // namespace dt
