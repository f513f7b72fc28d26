#include "render/gl_context.h"

#include <GL/gl.h>
#include <GL/osmesa.h>

#include <cstdlib>
#include <stdexcept>
#include <string_view>

#include <fmt/format.h>

namespace dt {

GlContext::GlContext() {
  // llvmpipe reads this once, when the first context creates its screen. With worker threads
  // the rasteriser bins work by tile; with none the order of every operation is fixed.
  // Written only when needed: setenv races with other threads reading the environment.
  const char* threads = std::getenv("LP_NUM_THREADS");
  if (threads == nullptr || std::string_view(threads) != "0") setenv("LP_NUM_THREADS", "0", 1);
  OSMesaContext ctx = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, nullptr);
  if (ctx == nullptr) throw std::runtime_error("OSMesaCreateContextExt failed");
  context_ = ctx;
}

GlContext::~GlContext() { OSMesaDestroyContext(static_cast<OSMesaContext>(context_)); }

void GlContext::Bind(int width_px, int height_px) {
  pixels_.assign(static_cast<size_t>(width_px) * static_cast<size_t>(height_px) * 4, 0);
  if (!OSMesaMakeCurrent(static_cast<OSMesaContext>(context_), pixels_.data(), GL_UNSIGNED_BYTE,
                         width_px, height_px)) {
    throw std::runtime_error(
        fmt::format("OSMesaMakeCurrent failed for a {} x {} px buffer", width_px, height_px));
  }
  OSMesaPixelStore(OSMESA_Y_UP, 0);
  glViewport(0, 0, width_px, height_px);
}

}  // namespace dt
