#include "ovpc/sim/renderer.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
// Only for OpenGL's types and constants: the functions are looked up through EGL, so nothing links
// libGL (MuJoCo finds its own through EGL too).
#include <GL/gl.h>
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "ovpc/sim/odometry.h"
#include "ovpc/sim/simulator.h"

namespace ovpc::sim {
namespace {

constexpr int kMaxSceneGeoms = 4000;

[[noreturn]] void Fail(const std::string& step) {
  char code[16];
  std::snprintf(code, sizeof(code), "0x%x", static_cast<unsigned>(eglGetError()));
  throw std::runtime_error("Renderer: " + step + " failed (EGL error " + code +
                           "); headless pictures need Debian libegl-mesa0 and libgl1-mesa-dri");
}

/// The legacy OpenGL calls the overlay needs, looked up through EGL.
struct Gl {
  decltype(&glBegin) Begin = nullptr;
  decltype(&glEnd) End = nullptr;
  decltype(&glVertex3d) Vertex3d = nullptr;
  decltype(&glColor4f) Color4f = nullptr;
  decltype(&glEnable) Enable = nullptr;
  decltype(&glDisable) Disable = nullptr;
  decltype(&glDepthFunc) DepthFunc = nullptr;
  decltype(&glBlendFunc) BlendFunc = nullptr;
  decltype(&glPolygonOffset) PolygonOffset = nullptr;
  decltype(&glPointSize) PointSize = nullptr;
  decltype(&glLineWidth) LineWidth = nullptr;
  decltype(&glMatrixMode) MatrixMode = nullptr;
  decltype(&glPushMatrix) PushMatrix = nullptr;
  decltype(&glPopMatrix) PopMatrix = nullptr;
  decltype(&glLoadIdentity) LoadIdentity = nullptr;
  decltype(&glLoadMatrixd) LoadMatrixd = nullptr;
  decltype(&glFrustum) Frustum = nullptr;
  decltype(&glViewport) Viewport = nullptr;
  decltype(&glPushAttrib) PushAttrib = nullptr;
  decltype(&glPopAttrib) PopAttrib = nullptr;
  decltype(&glGetString) GetString = nullptr;

  template <typename F>
  static void Load(F*& f, const char* name) {
    f = reinterpret_cast<F*>(eglGetProcAddress(name));
    if (f == nullptr) throw std::runtime_error(std::string("Renderer: OpenGL has no ") + name);
  }

  void LoadAll() {
    Load(Begin, "glBegin");
    Load(End, "glEnd");
    Load(Vertex3d, "glVertex3d");
    Load(Color4f, "glColor4f");
    Load(Enable, "glEnable");
    Load(Disable, "glDisable");
    Load(DepthFunc, "glDepthFunc");
    Load(BlendFunc, "glBlendFunc");
    Load(PolygonOffset, "glPolygonOffset");
    Load(PointSize, "glPointSize");
    Load(LineWidth, "glLineWidth");
    Load(MatrixMode, "glMatrixMode");
    Load(PushMatrix, "glPushMatrix");
    Load(PopMatrix, "glPopMatrix");
    Load(LoadIdentity, "glLoadIdentity");
    Load(LoadMatrixd, "glLoadMatrixd");
    Load(Frustum, "glFrustum");
    Load(Viewport, "glViewport");
    Load(PushAttrib, "glPushAttrib");
    Load(PopAttrib, "glPopAttrib");
    Load(GetString, "glGetString");
  }
};

EGLDisplay OpenSurfacelessDisplay() {
  // Mesa's surfaceless platform needs neither a display server nor a GPU.
  const char* client_extensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  const bool has_surfaceless = client_extensions != nullptr &&
                               std::string(client_extensions).find("EGL_MESA_platform_surfaceless") !=
                                   std::string::npos;
  const auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (has_surfaceless && get_platform_display != nullptr) {
    EGLDisplay display =
        get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (display != EGL_NO_DISPLAY) return display;
  }
  // Older stacks: the platform chosen through the environment (does not override the user's).
  setenv("EGL_PLATFORM", "surfaceless", 0);
  return eglGetDisplay(EGL_DEFAULT_DISPLAY);
}

}  // namespace

bool RendererAvailable() { return true; }

struct Renderer::Impl {
  const Simulator* sim = nullptr;
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  Gl gl;
  mjvScene scene;
  mjrContext con;
  mjvOption option;
  mjData* pose_data = nullptr;  ///< the simulator's positions, kinematics brought up to date
  bool scene_made = false;
  bool con_made = false;
  int width = 0;
  int height = 0;

  ~Impl() {
    if (context != EGL_NO_CONTEXT) {
      eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context);
      if (con_made) mjr_freeContext(&con);
      eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      eglDestroyContext(display, context);
    }
    if (scene_made) mjv_freeScene(&scene);
    if (pose_data != nullptr) mj_deleteData(pose_data);
    // The display stays initialised: other renderers in the process may share it.
  }

  void MakeCurrent() {
    if (eglGetCurrentContext() != context &&
        !eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
      Fail("eglMakeCurrent");
    }
  }

  void DrawOverlay(const Overlay& overlay);
};

Renderer::Renderer(const Simulator& sim) : impl_(std::make_unique<Impl>()) {
  Impl& r = *impl_;
  r.sim = &sim;
  r.display = OpenSurfacelessDisplay();
  if (r.display == EGL_NO_DISPLAY) Fail("eglGetPlatformDisplay (surfaceless)");
  EGLint major = 0;
  EGLint minor = 0;
  if (!eglInitialize(r.display, &major, &minor)) Fail("eglInitialize");
  const EGLint config_attributes[] = {EGL_RED_SIZE,     8,  EGL_GREEN_SIZE,      8,
                                      EGL_BLUE_SIZE,    8,  EGL_ALPHA_SIZE,      8,
                                      EGL_DEPTH_SIZE,   24, EGL_STENCIL_SIZE,    8,
                                      EGL_SURFACE_TYPE, EGL_PBUFFER_BIT,
                                      EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT,    EGL_NONE};
  EGLConfig config = nullptr;
  EGLint num_configs = 0;
  if (!eglChooseConfig(r.display, config_attributes, &config, 1, &num_configs) ||
      num_configs < 1) {
    Fail("eglChooseConfig (RGBA8, depth 24, pbuffer, OpenGL)");
  }
  if (!eglBindAPI(EGL_OPENGL_API)) Fail("eglBindAPI(EGL_OPENGL_API)");
  r.context = eglCreateContext(r.display, config, EGL_NO_CONTEXT, nullptr);
  if (r.context == EGL_NO_CONTEXT) Fail("eglCreateContext");
  r.MakeCurrent();
  r.gl.LoadAll();

  const mjModel* m = sim.model();
  mjv_defaultScene(&r.scene);
  mjv_makeScene(m, &r.scene, kMaxSceneGeoms);
  r.scene_made = true;
  r.scene.flags[mjRND_SHADOW] = 0;
  r.scene.flags[mjRND_REFLECTION] = 0;
  mjr_defaultContext(&r.con);
  mjr_makeContext(m, &r.con, mjFONTSCALE_100);
  r.con_made = true;
  mjr_setBuffer(mjFB_OFFSCREEN, &r.con);
  if (r.con.currentBuffer != mjFB_OFFSCREEN) {
    throw std::runtime_error("Renderer: MuJoCo could not use its offscreen buffer");
  }
  r.width = r.con.offWidth;
  r.height = r.con.offHeight;
  r.pose_data = mj_makeData(m);
  if (r.pose_data == nullptr) throw std::runtime_error("Renderer: mj_makeData failed");
  mjv_defaultOption(&r.option);
  r.option.geomgroup[2] = 0;  // the wheels' collision ellipsoids; their tyres are in group 1
}

Renderer::~Renderer() = default;

std::string Renderer::gl_renderer() const {
  impl_->MakeCurrent();
  const GLubyte* s = impl_->gl.GetString(GL_RENDERER);
  return s != nullptr ? reinterpret_cast<const char*>(s) : "";
}

Image Renderer::Render(const ChaseCamera& camera, const Overlay& overlay) {
  overlay.Validate();
  Impl& r = *impl_;
  r.MakeCurrent();
  const mjModel* m = r.sim->model();
  // After mj_step the simulator's body poses are those before the step's integration; draw the
  // current positions instead (the overlay is in the current frame too).
  const mjData* sim_data = r.sim->data();
  mjData* d = r.pose_data;
  std::copy_n(sim_data->qpos, m->nq, d->qpos);
  d->time = sim_data->time;
  mj_kinematics(m, d);
  mj_camlight(m, d);

  const Eigen::Isometry3d T_W_B = r.sim->T_W_B();
  const double heading = YawOf(T_W_B.linear());
  const Vec3 lookat = T_W_B.translation() +
                      camera.lookat_ahead_m * Vec3(std::cos(heading), std::sin(heading), 0.0) +
                      Vec3(0.0, 0.0, camera.lookat_height_m);
  mjvCamera cam;
  mjv_defaultCamera(&cam);
  cam.type = mjCAMERA_FREE;
  for (int i = 0; i < 3; ++i) cam.lookat[i] = lookat[i];
  cam.distance = camera.distance_m;
  cam.azimuth = RadToDeg(heading) + camera.azimuth_offset_deg;
  cam.elevation = camera.elevation_deg;

  mjv_updateScene(m, d, &r.option, nullptr, &cam, mjCAT_ALL, &r.scene);
  mjr_setBuffer(mjFB_OFFSCREEN, &r.con);
  const mjrRect viewport = {0, 0, r.width, r.height};
  mjr_render(viewport, &r.scene, &r.con);
  r.DrawOverlay(overlay);

  Image image;
  image.width = r.width;
  image.height = r.height;
  std::vector<unsigned char> bottom_up(3 * static_cast<std::size_t>(r.width) * r.height);
  mjr_readPixels(bottom_up.data(), nullptr, viewport, &r.con);
  image.rgb.resize(bottom_up.size());
  const std::size_t row = 3 * static_cast<std::size_t>(r.width);
  for (int y = 0; y < r.height; ++y) {
    std::copy_n(bottom_up.data() + row * static_cast<std::size_t>(r.height - 1 - y), row,
                image.rgb.data() + row * static_cast<std::size_t>(y));
  }
  return image;
}

void Renderer::Impl::DrawOverlay(const Overlay& overlay) {
  if (overlay.points.empty() && overlay.polylines.empty() && overlay.mesh_triangles.empty()) {
    return;
  }
  // The camera MuJoCo just used: the mean of its two (stereo) eyes, as in mono rendering.
  const mjvGLCamera& c0 = scene.camera[0];
  const mjvGLCamera& c1 = scene.camera[1];
  const Vec3 pos = 0.5 * (Vec3(c0.pos[0], c0.pos[1], c0.pos[2]) + Vec3(c1.pos[0], c1.pos[1], c1.pos[2]));
  const Vec3 forward =
      (Vec3(c0.forward[0], c0.forward[1], c0.forward[2]) + Vec3(c1.forward[0], c1.forward[1], c1.forward[2]))
          .normalized();
  const Vec3 up_hint =
      (Vec3(c0.up[0], c0.up[1], c0.up[2]) + Vec3(c1.up[0], c1.up[1], c1.up[2])).normalized();
  const Vec3 side = forward.cross(up_hint).normalized();
  const Vec3 up = side.cross(forward);
  Eigen::Matrix4d view = Eigen::Matrix4d::Identity();
  view.block<1, 3>(0, 0) = side.transpose();
  view.block<1, 3>(1, 0) = up.transpose();
  view.block<1, 3>(2, 0) = -forward.transpose();
  view.block<3, 1>(0, 3) = -view.block<3, 3>(0, 0) * pos;
  const double bottom = 0.5 * (c0.frustum_bottom + c1.frustum_bottom);
  const double top = 0.5 * (c0.frustum_top + c1.frustum_top);
  const double centre = 0.5 * (c0.frustum_center + c1.frustum_center);
  const double near = 0.5 * (c0.frustum_near + c1.frustum_near);
  const double far = 0.5 * (c0.frustum_far + c1.frustum_far);
  const double half_width = 0.5 * width / height * (top - bottom);

  gl.PushAttrib(GL_ALL_ATTRIB_BITS);
  gl.Viewport(0, 0, width, height);
  gl.MatrixMode(GL_PROJECTION);
  gl.PushMatrix();
  gl.LoadIdentity();
  gl.Frustum(centre - half_width, centre + half_width, bottom, top, near, far);
  gl.MatrixMode(GL_MODELVIEW);
  gl.PushMatrix();
  gl.LoadMatrixd(view.data());  // Eigen is column-major, as OpenGL expects
  gl.Disable(GL_LIGHTING);
  gl.Disable(GL_TEXTURE_2D);
  gl.Disable(GL_CULL_FACE);
  gl.Enable(GL_BLEND);
  gl.BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  if (overlay.depth_test) {
    gl.Enable(GL_DEPTH_TEST);
    gl.DepthFunc(GL_LEQUAL);
  } else {
    gl.Disable(GL_DEPTH_TEST);
  }

  if (!overlay.mesh_triangles.empty()) {
    // Pulled towards the camera so that a mesh lying on the terrain wins the depth test.
    gl.Enable(GL_POLYGON_OFFSET_FILL);
    gl.PolygonOffset(-1.0f, -4.0f);
    gl.Begin(GL_TRIANGLES);
    for (std::size_t f = 0; f < overlay.mesh_triangles.size(); ++f) {
      const Triangle& t = overlay.mesh_triangles[f];
      const Vec3& a = overlay.mesh_vertices_W[static_cast<std::size_t>(t[0])];
      const Vec3& b = overlay.mesh_vertices_W[static_cast<std::size_t>(t[1])];
      const Vec3& cc = overlay.mesh_vertices_W[static_cast<std::size_t>(t[2])];
      const Vec3 normal = (b - a).cross(cc - a);
      const double n = normal.norm();
      // Unlit faces shaded by slope, so the mesh's shape reads.
      const float shade = n > 0.0 ? static_cast<float>(0.55 + 0.45 * std::abs(normal.z()) / n) : 1.0f;
      const Rgba& rgba = overlay.mesh_face_rgba[f];
      gl.Color4f(shade * rgba[0], shade * rgba[1], shade * rgba[2], rgba[3]);
      gl.Vertex3d(a.x(), a.y(), a.z());
      gl.Vertex3d(b.x(), b.y(), b.z());
      gl.Vertex3d(cc.x(), cc.y(), cc.z());
    }
    gl.End();
    gl.Disable(GL_POLYGON_OFFSET_FILL);
  }
  for (const Overlay::Polyline& line : overlay.polylines) {
    gl.LineWidth(line.width_px);
    gl.Color4f(line.rgba[0], line.rgba[1], line.rgba[2], line.rgba[3]);
    gl.Begin(GL_LINE_STRIP);
    for (const Vec3& v : line.vertices_W) gl.Vertex3d(v.x(), v.y(), v.z());
    gl.End();
  }
  if (!overlay.points.empty()) {
    gl.PointSize(overlay.point_size_px);
    gl.Begin(GL_POINTS);
    for (const Overlay::Point& p : overlay.points) {
      gl.Color4f(p.rgba[0], p.rgba[1], p.rgba[2], p.rgba[3]);
      gl.Vertex3d(p.position_W.x(), p.position_W.y(), p.position_W.z());
    }
    gl.End();
  }

  gl.MatrixMode(GL_MODELVIEW);
  gl.PopMatrix();
  gl.MatrixMode(GL_PROJECTION);
  gl.PopMatrix();
  gl.PopAttrib();
}

}  // namespace ovpc::sim
