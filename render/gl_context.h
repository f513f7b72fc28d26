// GlContext: an OSMesa off-screen OpenGL context (CPU rendering, no display, no GPU).
#pragma once

#include <cstdint>
#include <vector>

namespace dt {

// Owns one OSMesa context with a 24-bit depth buffer rendering into memory owned here, row 0 at
// the top. The first context of the process sets LP_NUM_THREADS=0 so llvmpipe rasterises on the
// calling thread only: the same commands then give the same pixels (docs/rendering.md).
// Not thread-safe: one thread uses a context at a time.
class GlContext {
 public:
  // Throws std::runtime_error if OSMesa cannot create a context.
  GlContext();
  ~GlContext();
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  // Makes the context current on this thread with a width x height RGBA colour buffer.
  // Throws std::runtime_error if OSMesa refuses.
  void Bind(int width_px, int height_px);
  // The colour buffer after glFinish(): 4 bytes per pixel, row 0 at the top.
  const std::vector<uint8_t>& pixels() const { return pixels_; }

 private:
  void* context_ = nullptr;  // OSMesaContext, kept opaque so GL headers stay out of this header
  std::vector<uint8_t> pixels_;
};

}  // namespace dt
