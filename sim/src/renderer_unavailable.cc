// Built instead of renderer.cc and image.cc when EGL or libpng was not found: the simulator works,
// pictures do not (every call says why).
#include <stdexcept>
#include <string>

#include "ovpc/sim/image.h"
#include "ovpc/sim/renderer.h"

namespace ovpc::sim {
namespace {

[[noreturn]] void Unavailable() {
  throw std::runtime_error(
      "ovpc::sim was built without headless rendering (CMake did not find EGL and libpng; "
      "install Debian libegl-dev, libegl-mesa0, libgl1-mesa-dri and libpng-dev, then reconfigure)");
}

}  // namespace

bool RendererAvailable() { return false; }

struct Renderer::Impl {};

Renderer::Renderer(const Simulator& /*sim*/) { Unavailable(); }
Renderer::~Renderer() = default;
Image Renderer::Render(const ChaseCamera& /*camera*/, const Overlay& /*overlay*/) { Unavailable(); }
std::string Renderer::gl_renderer() const { Unavailable(); }

void WritePng(const Image& /*image*/, const std::string& /*path*/) { Unavailable(); }

}  // namespace ovpc::sim
