// The "osmesa" backend: OpenGL 4.5 core on llvmpipe through OSMesa, rendering a PipelinePlan into FBOs.
// Draws are timed with a wall clock around state setup + draw + glFinish: GL timer queries do not see
// llvmpipe's rasteriser threads (docs/architecture.md, "Rendering and timing").
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdlib>
#include <map>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "render/backend.h"
#include "render/osmesa_gl.h"
#include "render/osmesa_internal.h"
#include "shadergen/bindings.h"

namespace aovar::render {
namespace osmesa {

const char* load_gl_functions(GlFunctions& gl) {
  // OSMesaGetProcAddress hands out dispatch stubs even for unknown names, so a null here means a broken
  // library rather than an old one; checked all the same.
#define AOVAR_GL_LOAD(type, name)                                        \
  gl.name = reinterpret_cast<type>(OSMesaGetProcAddress("gl" #name)); \
  if (!gl.name) return "gl" #name;
  AOVAR_GL_FUNCTIONS(AOVAR_GL_LOAD)
#undef AOVAR_GL_LOAD
  return nullptr;
}

std::size_t GlNames::size() const {
  return textures.size() + renderbuffers.size() + framebuffers.size() + buffers.size() + programs.size() +
         shaders.size();
}

namespace {

// GL binds by the template contract's numbers (shadergen/bindings.h): uniform block bindings for the two
// blocks, texture units for the samplers.
constexpr int kFirstTextureUnit = shadergen::binding::kFirstSampler;
constexpr int kTextureUnits = shadergen::binding::kSamplerCount;

// llvmpipe reads LP_NUM_THREADS once per process, when OSMesa creates its only screen, and that happens
// on the first context request even if the request fails (measured). Later contexts keep those threads.
std::mutex g_threads_mutex;
int g_screen_threads = -1;

std::string one_line(std::string s, std::size_t max_chars = 400) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ' || s.back() == '\0')) s.pop_back();
  for (std::size_t i = 0; (i = s.find('\n', i)) != std::string::npos;) s.replace(i, 1, " | ");
  if (s.size() > max_chars) s = s.substr(0, max_chars) + " ...";
  return s;
}

// The OSMesa context and its function table, shared by the backend and the pipelines it prepared so that
// either may be destroyed first.
struct Context {
  OSMesaContext ctx = nullptr;
  std::array<unsigned char, 4 * 16 * 16> default_buffer{};  // the window-system buffer; never drawn to
  GlFunctions gl;

  Context(const BackendOptions& options, int major, int minor) {
    if (options.mediump_as_fp16)
      throw BackendError("osmesa: mediump as fp16 is lavapipe only (it rewrites Vulkan SPIR-V; OpenGL GLSL "
                         "mediump stays fp32 on llvmpipe): use the lavapipe backend");
    {
      std::lock_guard lock(g_threads_mutex);
      if (options.threads < 0)
        throw BackendError(fmt::format("osmesa: invalid thread count {} (use 0 or more)", options.threads));
      if (g_screen_threads >= 0 && g_screen_threads != options.threads)
        throw BackendError(fmt::format(
            "osmesa: llvmpipe already runs {} threads in this process and reads LP_NUM_THREADS only once; "
            "use a separate process for {} threads", g_screen_threads, options.threads));
      setenv("LP_NUM_THREADS", std::to_string(options.threads).c_str(), 1);
      g_screen_threads = options.threads;
    }
    const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION, major, OSMESA_CONTEXT_MINOR_VERSION, minor, 0};
    ctx = OSMesaCreateContextAttribs(attribs, nullptr);
    if (!ctx)
      throw BackendError(fmt::format("osmesa: OSMesaCreateContextAttribs failed for an OpenGL {}.{} core context "
                                     "(OSMesa must provide GL 4.5 core: install libosmesa6 via scripts/deps)",
                                     major, minor));
    try {
      make_current();
      if (const char* missing = load_gl_functions(gl))
        throw BackendError(fmt::format("osmesa: the driver lacks {} (OSMesa must provide GL 4.5 core: install "
                                       "libosmesa6 via scripts/deps)", missing));
    } catch (...) {
      release();
      throw;
    }
  }
  ~Context() { release(); }
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  // Contexts are per thread and a process may hold several (tests create them in turn): every entry
  // point makes its own current. Cheap when it already is.
  void make_current() {
    if (OSMesaGetCurrentContext() == ctx) return;
    if (!OSMesaMakeCurrent(ctx, default_buffer.data(), GL_UNSIGNED_BYTE, 16, 16))
      throw BackendError("osmesa: OSMesaMakeCurrent failed (OSMesa must provide GL 4.5 core: install libosmesa6 "
                         "via scripts/deps)");
  }

  void release() {
    if (!ctx) return;
    if (OSMesaGetCurrentContext() == ctx) OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0);
    OSMesaDestroyContext(ctx);
    ctx = nullptr;
  }

  // One glGetError per call site: errors stick until read, so this catches anything since the last check.
  // `where` is formatted only when there is an error.
  template <class... Args>
  void check(fmt::format_string<Args...> where, Args&&... args) {
    GLenum e = gl.GetError();
    if (e == GL_NO_ERROR) return;
    std::string codes = fmt::format("0x{:04x}", e);
    for (int i = 0; i < 8 && (e = gl.GetError()) != GL_NO_ERROR; ++i) codes += fmt::format(", 0x{:04x}", e);
    throw BackendError(fmt::format("osmesa: GL error {} {}", codes, fmt::format(where, std::forward<Args>(args)...)));
  }
};

GLenum internal_format(Format f) {
  switch (f) {
    case Format::r16f: return GL_R16F;
    case Format::r32f: return GL_R32F;
    case Format::rgba8: return GL_RGBA8;
    case Format::rg8: return GL_RG8;
    case Format::rgba32f: return GL_RGBA32F;
  }
  throw BackendError("osmesa: unknown texture format");
}

float resolve_clear(float v, float far_plane) {
  if (v == kClearFar) return far_plane;
  if (v == kClearNegFar) return -far_plane;
  return v;
}

// One draw of the plan with every GL name and value it needs, so the timed loop only issues GL calls.
struct GlDraw {
  std::string name;
  bool geometry = false;
  DepthUse depth = DepthUse::none;
  Extent viewport;
  GLuint program = 0;
  GLuint params = 0;                                  // AOParams UBO, 0 = the draw has no block
  std::size_t param_count = 0;                        // floats in the block (set_params must match)
  std::array<GLuint, 2> fbo{};                        // by frame parity (the same FBO twice if it has none)
  std::array<std::array<GLuint, kTextureUnits>, 2> units{};  // texture per sampler unit, by frame parity
  struct Clear {
    GLint location = 0;
    std::array<float, 4> raw{}, value{};  // raw may hold kClearFar / kClearNegFar; value is this frame's
  };
  std::vector<Clear> clears;  // colour attachments this draw clears first (it writes them first in a frame)
};

class OsmesaPipeline final : public PreparedPipeline {
 public:
  OsmesaPipeline(std::shared_ptr<Context> c, std::string variant) : c_(std::move(c)), variant_(std::move(variant)) {}

  ~OsmesaPipeline() override {
    try {
      c_->make_current();
    } catch (const BackendError&) {
      return;  // the context is gone or unusable: its objects went with it
    }
    GlFunctions& gl = c_->gl;
    if (!names_.framebuffers.empty())
      gl.DeleteFramebuffers(GLsizei(names_.framebuffers.size()), names_.framebuffers.data());
    if (!names_.renderbuffers.empty())
      gl.DeleteRenderbuffers(GLsizei(names_.renderbuffers.size()), names_.renderbuffers.data());
    if (!names_.textures.empty()) gl.DeleteTextures(GLsizei(names_.textures.size()), names_.textures.data());
    if (!names_.buffers.empty()) gl.DeleteBuffers(GLsizei(names_.buffers.size()), names_.buffers.data());
    for (GLuint s : live_shaders_) gl.DeleteShader(s);
    gl.UseProgram(0);  // a program in use is only flagged for deletion
    for (GLuint p : names_.programs) gl.DeleteProgram(p);
    gl.GetError();  // nothing to report from a destructor
  }

  std::shared_ptr<Context> c_;
  std::string variant_;
  Extent size_, ao_;
  GlNames names_;
  std::vector<GLuint> live_shaders_;        // shader objects not yet deleted (prepare failed midway)
  std::vector<std::array<GLuint, 2>> tex_;  // per plan texture: copy by parity (equal when single)
  std::vector<Extent> tex_size_;
  std::map<std::pair<GLuint, int>, GLuint> level_views_;  // (texture, level) -> view of that level alone

  // A texture view of one MIP level (created once), so a draw can read level l while writing level l + 1.
  GLuint level_view(GLuint texture, int level, GLenum format) {
    auto [it, fresh] = level_views_.emplace(std::make_pair(texture, level), 0u);
    if (!fresh) return it->second;
    GlFunctions& gl = c_->gl;
    gl.GenTextures(1, &it->second);  // a view needs a name that was never bound
    names_.textures.push_back(it->second);
    gl.TextureView(it->second, GL_TEXTURE_2D, texture, format, GLuint(level), 1, 0, 1);
    gl.TextureParameteri(it->second, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    gl.TextureParameteri(it->second, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    return it->second;
  }
  GLuint frame_ubo_ = 0;
  std::vector<GlDraw> draws_;
  int result_ = -1;
  int last_parity_ = -1;  // parity of the last rendered frame, -1 before the first
};

class OsmesaBackend final : public Backend {
 public:
  OsmesaBackend(const BackendOptions& options, int major, int minor)
      : c_(std::make_shared<Context>(options, major, minor)) {
    GlFunctions& gl = c_->gl;
    auto str = [&](GLenum e) {
      const GLubyte* s = gl.GetString(e);
      return s ? std::string(reinterpret_cast<const char*>(s)) : std::string();
    };
    std::string version = str(GL_VERSION);  // "4.5 (Core Profile) Mesa 22.3.6"
    info_.backend = "osmesa";
    info_.device = str(GL_RENDERER);
    info_.api_version = "OpenGL " + version;
    if (auto at = version.find("Mesa "); at != std::string::npos)
      info_.driver = version.substr(at, version.find(' ', at + 5) - at);
    info_.threads = options.threads;
    // GLSL 4.50 section 4.7: precision qualifiers have no meaning in desktop GLSL, and llvmpipe runs fp32.
    info_.ignores_relaxed_precision = true;
    info_.precision = "mediump runs in fp32 (desktop GLSL ignores precision qualifiers)";

    // Fixed state: fullscreen triangles change winding with the y direction, and nothing blends.
    gl.Disable(GL_CULL_FACE);
    gl.Disable(GL_BLEND);
    gl.Disable(GL_SCISSOR_TEST);
    gl.Disable(GL_DITHER);
    gl.DepthFunc(GL_LESS);
    gl.CreateVertexArrays(1, &empty_vao_);  // core profile draws need a VAO even without attributes
    gl.CreateVertexArrays(1, &scene_vao_);
    c_->check("creating the context");
  }

  ~OsmesaBackend() override {
    try {
      c_->make_current();
    } catch (const BackendError&) {
      return;
    }
    GlFunctions& gl = c_->gl;
    gl.DeleteVertexArrays(1, &empty_vao_);
    gl.DeleteVertexArrays(1, &scene_vao_);
    gl.DeleteBuffers(GLsizei(scene_buffers_.size()), scene_buffers_.data());
    gl.GetError();
  }

  const DeviceInfo& info() const override { return info_; }
  ClipDepth clip_depth() const override { return ClipDepth::minus_one_to_one; }  // no glClipControl

  void set_scene(const scene::Scene& scene) override {
    // Check before touching the current scene, so a rejected one leaves the previous scene in place.
    if (scene.normals.size() != scene.positions.size())
      throw BackendError(fmt::format("osmesa: scene {} has {} normals for {} positions", scene.name,
                                     scene.normals.size(), scene.positions.size()));
    if (scene.indices.size() % 3 != 0)
      throw BackendError(fmt::format("osmesa: scene {} has {} indices, not whole triangles", scene.name,
                                     scene.indices.size()));
    for (std::uint32_t i : scene.indices)
      if (i >= scene.positions.size())
        throw BackendError(fmt::format("osmesa: scene {} indexes vertex {} of {}", scene.name, i,
                                       scene.positions.size()));
    c_->make_current();
    GlFunctions& gl = c_->gl;
    gl.DeleteBuffers(GLsizei(scene_buffers_.size()), scene_buffers_.data());
    scene_buffers_ = {};
    index_count_ = 0;
    gl.CreateBuffers(3, scene_buffers_.data());
    // Zero-sized storage is an error in GL; one spare byte keeps empty scenes legal (nothing is drawn).
    auto store = [&](GLuint buffer, std::size_t bytes, const void* data) {
      gl.NamedBufferStorage(buffer, GLsizeiptr(std::max<std::size_t>(bytes, 4)), bytes ? data : nullptr,
                            bytes ? 0 : GL_DYNAMIC_STORAGE_BIT);
    };
    store(scene_buffers_[0], scene.positions.size() * sizeof(glm::vec3), scene.positions.data());
    store(scene_buffers_[1], scene.normals.size() * sizeof(glm::vec3), scene.normals.data());
    store(scene_buffers_[2], scene.indices.size() * sizeof(std::uint32_t), scene.indices.data());
    for (GLuint a = 0; a < 2; ++a) {  // location 0 a_position, 1 a_normal; one buffer binding each
      gl.VertexArrayVertexBuffer(scene_vao_, a, scene_buffers_[a], 0, sizeof(glm::vec3));
      gl.VertexArrayAttribFormat(scene_vao_, a, 3, GL_FLOAT, GL_FALSE, 0);
      gl.VertexArrayAttribBinding(scene_vao_, a, a);
      gl.EnableVertexArrayAttrib(scene_vao_, a);
    }
    gl.VertexArrayElementBuffer(scene_vao_, scene_buffers_[2]);
    index_count_ = GLsizei(scene.indices.size());
    has_scene_ = true;
    c_->check("uploading scene {}", scene.name);
  }

  std::unique_ptr<PreparedPipeline> prepare(const PipelinePlan& plan, Extent size) override;
  std::vector<double> render(PreparedPipeline& pipeline, const FrameSetup& frame) override;
  image::FloatImage read_result(PreparedPipeline& pipeline) override;
  void set_params(PreparedPipeline& pipeline, std::size_t draw, const std::vector<float>& params) override;

  std::size_t count_live(const GlNames& n) {
    c_->make_current();
    GlFunctions& gl = c_->gl;
    std::size_t live = 0;
    auto count = [&](const std::vector<unsigned>& names, PFNGLISTEXTUREPROC is) {
      for (unsigned name : names) live += is(name) ? 1 : 0;
    };
    count(n.textures, gl.IsTexture);
    count(n.renderbuffers, gl.IsRenderbuffer);
    count(n.framebuffers, gl.IsFramebuffer);
    count(n.buffers, gl.IsBuffer);
    count(n.programs, gl.IsProgram);
    count(n.shaders, gl.IsShader);
    return live;
  }

 private:
  OsmesaPipeline& own(PreparedPipeline& pipeline) {
    auto* p = dynamic_cast<OsmesaPipeline*>(&pipeline);
    if (!p || p->c_ != c_) throw BackendError("osmesa: pipeline was prepared by another backend");
    return *p;
  }

  // Each shader compiled once, each (vertex, fragment) pair linked once, per prepare().
  struct Programs {
    std::map<int, GLuint> shaders;
    std::map<std::pair<int, int>, GLuint> linked;
  };

  // The steps of prepare(), in order; the GL objects go into the pipeline's names as they are created.
  void create_textures(const PipelinePlan& plan, OsmesaPipeline& p);
  std::vector<GLuint> create_depth_buffers(const PipelinePlan& plan, OsmesaPipeline& p);
  GlDraw gl_draw(const PipelinePlan& plan, const Draw& d, OsmesaPipeline& p, Programs& programs,
                 const std::vector<GLuint>& depth_buffers, std::vector<bool>& written);
  GLuint program(const PipelinePlan& plan, const Draw& d, OsmesaPipeline& p, Programs& programs);
  void upload_params(const Draw& d, OsmesaPipeline& p, GlDraw& g);
  void bind_inputs(const PipelinePlan& plan, const Draw& d, OsmesaPipeline& p, GlDraw& g);
  void create_framebuffers(const PipelinePlan& plan, const Draw& d, const std::vector<GLuint>& depth_buffers,
                           OsmesaPipeline& p, GlDraw& g);

  GLuint compile(OsmesaPipeline& p, const Shader& s) {
    GlFunctions& gl = c_->gl;
    GLuint shader = gl.CreateShader(s.stage == variants::StageKind::vertex ? GL_VERTEX_SHADER : GL_FRAGMENT_SHADER);
    p.names_.shaders.push_back(shader);
    p.live_shaders_.push_back(shader);
    const char* src = s.glsl.c_str();
    GLint len = GLint(s.glsl.size());
    gl.ShaderSource(shader, 1, &src, &len);
    gl.CompileShader(shader);
    GLint ok = GL_FALSE;
    gl.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
      std::string log(4096, '\0');
      GLsizei n = 0;
      gl.GetShaderInfoLog(shader, GLsizei(log.size()), &n, log.data());
      log.resize(std::max<GLsizei>(n, 0));
      throw BackendError(fmt::format("osmesa: {} ({}): GLSL compile failed: {}", s.program_key, p.variant_,
                                     s.glsl.empty() ? "no GLSL source (was the gl45 target compiled?)" : one_line(log)));
    }
    return shader;
  }

  std::shared_ptr<Context> c_;
  DeviceInfo info_;
  GLuint empty_vao_ = 0, scene_vao_ = 0;
  std::array<GLuint, 3> scene_buffers_{};  // positions, normals, indices
  GLsizei index_count_ = 0;
  bool has_scene_ = false;
};

std::unique_ptr<PreparedPipeline> OsmesaBackend::prepare(const PipelinePlan& full_plan, Extent size) {
  auto start = std::chrono::steady_clock::now();
  const PipelinePlan plan = plan_for_size(full_plan, size);
  c_->make_current();
  GlFunctions& gl = c_->gl;
  c_->check("before prepare");
  if (size.width <= 0 || size.height <= 0)
    throw BackendError(fmt::format("osmesa: invalid output size {}x{}", size.width, size.height));
  validate_plan(plan, "osmesa");
  // Built inside the pipeline object so that a throw part-way deletes what was already created.
  auto p = std::make_unique<OsmesaPipeline>(c_, plan.variant);
  p->size_ = size;
  p->ao_ = ao_extent(size, plan.resolution);
  p->result_ = plan.result;

  create_textures(plan, *p);
  const std::vector<GLuint> depth_buffers = create_depth_buffers(plan, *p);
  // AOFrame, filled by render.
  gl.CreateBuffers(1, &p->frame_ubo_);
  p->names_.buffers.push_back(p->frame_ubo_);
  gl.NamedBufferStorage(p->frame_ubo_, sizeof(FrameBlock), nullptr, GL_DYNAMIC_STORAGE_BIT);
  Programs programs;
  std::vector<bool> written(plan.textures.size(), false);  // by a draw before this one
  for (const Draw& d : plan.draws) p->draws_.push_back(gl_draw(plan, d, *p, programs, depth_buffers, written));

  // Shaders are owned by their programs once linked.
  for (GLuint s : p->live_shaders_) gl.DeleteShader(s);
  p->live_shaders_.clear();
  c_->check("while preparing {}", plan.variant);
  p->create_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return p;
}

// Textures: double-buffered ones start open (1.0) so that frame 0 reads a defined history.
void OsmesaBackend::create_textures(const PipelinePlan& plan, OsmesaPipeline& p) {
  GlFunctions& gl = c_->gl;
  for (const Texture& t : plan.textures) {
    Extent e = t.full_resolution ? p.size_ : p.ao_;
    std::array<GLuint, 2> copies{};
    int n = t.double_buffered ? 2 : 1;
    gl.CreateTextures(GL_TEXTURE_2D, n, copies.data());
    for (int i = 0; i < n; ++i) {
      p.names_.textures.push_back(copies[i]);
      gl.TextureStorage2D(copies[i], std::max(t.levels, 1), internal_format(t.format), e.width, e.height);
      // Every read is a texelFetch; a mipmapped filter keeps levels > 0 inside the texture's level range.
      gl.TextureParameteri(copies[i], GL_TEXTURE_MIN_FILTER, t.levels > 1 ? GL_NEAREST_MIPMAP_NEAREST : GL_NEAREST);
      gl.TextureParameteri(copies[i], GL_TEXTURE_MAG_FILTER, GL_NEAREST);
      gl.TextureParameteri(copies[i], GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
      gl.TextureParameteri(copies[i], GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
      if (t.double_buffered) {
        const float one[4] = {1, 1, 1, 1};
        gl.ClearTexImage(copies[i], 0, GL_RGBA, GL_FLOAT, one);
      }
    }
    if (n == 1) copies[1] = copies[0];
    p.tex_.push_back(copies);
    p.tex_size_.push_back(e);
  }
}

// Depth buffers: the G-buffer's, the background mask (plan.h).
std::vector<GLuint> OsmesaBackend::create_depth_buffers(const PipelinePlan& plan, OsmesaPipeline& p) {
  GlFunctions& gl = c_->gl;
  std::vector<GLuint> buffers;
  for (const DepthBuffer& b : plan.depth_buffers) {
    GLuint rb = 0;
    gl.CreateRenderbuffers(1, &rb);
    p.names_.renderbuffers.push_back(rb);
    const Extent e = b.full_resolution ? p.size_ : p.ao_;
    gl.NamedRenderbufferStorage(rb, GL_DEPTH_COMPONENT32F, e.width, e.height);
    buffers.push_back(rb);
  }
  return buffers;
}

// Draw `d` with every GL name it needs. `written` marks the textures earlier draws wrote: the first draw
// to write a texture clears it when the texture asks for a clear.
GlDraw OsmesaBackend::gl_draw(const PipelinePlan& plan, const Draw& d, OsmesaPipeline& p, Programs& programs,
                              const std::vector<GLuint>& depth_buffers, std::vector<bool>& written) {
  GlDraw g;
  g.name = d.name;
  g.geometry = d.geometry;
  g.depth = d.depth;
  g.viewport = d.full_resolution ? p.size_ : p.ao_;
  g.viewport.width = std::max(1, g.viewport.width >> d.level);
  g.viewport.height = std::max(1, g.viewport.height >> d.level);
  g.program = program(plan, d, p, programs);
  upload_params(d, p, g);
  bind_inputs(plan, d, p, g);
  create_framebuffers(plan, d, depth_buffers, p, g);
  for (std::size_t loc = 0; loc < d.outputs.size(); ++loc) {
    int t = d.outputs[loc].texture;
    if (t < 0 || written[t]) continue;
    written[t] = true;
    if (plan.textures[t].cleared) g.clears.push_back({GLint(loc), plan.textures[t].clear, plan.textures[t].clear});
  }
  return g;
}

GLuint OsmesaBackend::program(const PipelinePlan& plan, const Draw& d, OsmesaPipeline& p, Programs& programs) {
  auto key = std::make_pair(d.vertex, d.fragment);
  if (auto it = programs.linked.find(key); it != programs.linked.end()) return it->second;
  auto shader = [&](int index) {
    auto it = programs.shaders.find(index);
    if (it == programs.shaders.end()) it = programs.shaders.emplace(index, compile(p, plan.shaders[index])).first;
    return it->second;
  };
  GlFunctions& gl = c_->gl;
  GLuint vs = shader(d.vertex), fs = shader(d.fragment);
  GLuint prog = gl.CreateProgram();
  p.names_.programs.push_back(prog);
  gl.AttachShader(prog, vs);
  gl.AttachShader(prog, fs);
  gl.LinkProgram(prog);
  gl.DetachShader(prog, vs);
  gl.DetachShader(prog, fs);
  GLint ok = GL_FALSE;
  gl.GetProgramiv(prog, GL_LINK_STATUS, &ok);
  if (!ok) {
    std::string log(4096, '\0');
    GLsizei n = 0;
    gl.GetProgramInfoLog(prog, GLsizei(log.size()), &n, log.data());
    log.resize(std::max<GLsizei>(n, 0));
    throw BackendError(fmt::format("osmesa: {} + {} ({}): GLSL link failed: {}", plan.shaders[d.vertex].program_key,
                                   plan.shaders[d.fragment].program_key, plan.variant, one_line(log)));
  }
  programs.linked.emplace(key, prog);
  return prog;
}

// The draw's AOParams block, when it has one. std140: consecutive floats at 4 * i; the block's size
// rounds up to a vec4.
void OsmesaBackend::upload_params(const Draw& d, OsmesaPipeline& p, GlDraw& g) {
  if (d.params.empty()) return;
  GlFunctions& gl = c_->gl;
  std::vector<float> block((d.params.size() + 3) / 4 * 4, 0.0f);
  std::copy(d.params.begin(), d.params.end(), block.begin());
  gl.CreateBuffers(1, &g.params);
  p.names_.buffers.push_back(g.params);
  gl.NamedBufferStorage(g.params, GLsizeiptr(block.size() * sizeof(float)), block.data(), GL_DYNAMIC_STORAGE_BIT);
  g.param_count = d.params.size();
}

// Inputs by parity: at parity q the current copy of a double-buffered texture is q, the previous 1 - q.
void OsmesaBackend::bind_inputs(const PipelinePlan& plan, const Draw& d, OsmesaPipeline& p, GlDraw& g) {
  for (const auto& [binding, ref] : d.inputs) {
    const int unit = binding - kFirstTextureUnit;
    for (int q = 0; q < 2; ++q) {
      GLuint tex = p.tex_[ref.texture][ref.previous ? 1 - q : q];
      g.units[q][unit] =
          ref.level < 0 ? tex : p.level_view(tex, ref.level, internal_format(plan.textures[ref.texture].format));
    }
  }
}

// Framebuffers: location i -> GL_COLOR_ATTACHMENTi (GL_NONE where the plan leaves a location unused); one
// per parity when the draw writes a double-buffered texture.
void OsmesaBackend::create_framebuffers(const PipelinePlan& plan, const Draw& d,
                                        const std::vector<GLuint>& depth_buffers, OsmesaPipeline& p, GlDraw& g) {
  GlFunctions& gl = c_->gl;
  bool parity_dependent = false;
  for (const TextureRef& r : d.outputs)
    if (r.texture >= 0) parity_dependent |= plan.textures[r.texture].double_buffered;
  std::vector<GLenum> buffers(d.outputs.size(), GL_NONE);
  for (int q = 0; q < (parity_dependent ? 2 : 1); ++q) {
    GLuint fbo = 0;
    gl.CreateFramebuffers(1, &fbo);
    p.names_.framebuffers.push_back(fbo);
    for (std::size_t loc = 0; loc < d.outputs.size(); ++loc) {
      const TextureRef& r = d.outputs[loc];
      if (r.texture < 0) continue;
      gl.NamedFramebufferTexture(fbo, GLenum(GL_COLOR_ATTACHMENT0 + loc), p.tex_[r.texture][q], std::max(r.level, 0));
      buffers[loc] = GLenum(GL_COLOR_ATTACHMENT0 + loc);
    }
    if (d.depth_buffer >= 0)
      gl.NamedFramebufferRenderbuffer(fbo, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_buffers[d.depth_buffer]);
    gl.NamedFramebufferDrawBuffers(fbo, GLsizei(buffers.size()), buffers.data());
    GLenum status = gl.CheckNamedFramebufferStatus(fbo, GL_DRAW_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
      throw BackendError(fmt::format("osmesa: {}: framebuffer of draw {} is incomplete (status 0x{:04x})",
                                     plan.variant, d.name, status));
    g.fbo[q] = fbo;
  }
  if (!parity_dependent) g.fbo[1] = g.fbo[0];
}

std::vector<double> OsmesaBackend::render(PreparedPipeline& pipeline, const FrameSetup& frame) {
  OsmesaPipeline& p = own(pipeline);
  c_->make_current();
  GlFunctions& gl = c_->gl;
  if (!frame.view) throw BackendError("osmesa: render without a view");
  bool geometry = std::any_of(p.draws_.begin(), p.draws_.end(), [](const GlDraw& d) { return d.geometry; });
  if (geometry && !has_scene_) throw BackendError("osmesa: render before set_scene");

  FrameBlock block = make_frame_block(frame, p.size_, p.ao_, ClipDepth::minus_one_to_one);
  gl.NamedBufferSubData(p.frame_ubo_, 0, sizeof block, &block);
  gl.BindBufferBase(GL_UNIFORM_BUFFER, shadergen::binding::kFrame, p.frame_ubo_);
  for (GlDraw& d : p.draws_)
    for (GlDraw::Clear& c : d.clears)
      for (int i = 0; i < 4; ++i) c.value[i] = resolve_clear(c.raw[i], background_depth(frame.view->far_plane));
  const int parity = frame.frame & 1;
  std::vector<double> times(p.draws_.size(), 0.0);
  c_->check("before the first draw of {}", p.variant_);
  gl.Finish();  // earlier work (uploads, the previous frame) must not land in the first draw's time

  const float far_depth = 1.0f, no_background = 0.0f;
  for (std::size_t i = 0; i < p.draws_.size(); ++i) {
    const GlDraw& d = p.draws_[i];
    auto t0 = std::chrono::steady_clock::now();
    gl.BindFramebuffer(GL_DRAW_FRAMEBUFFER, d.fbo[parity]);
    gl.Viewport(0, 0, d.viewport.width, d.viewport.height);
    switch (d.depth) {
      case DepthUse::none:
        gl.Disable(GL_DEPTH_TEST);
        gl.DepthMask(GL_FALSE);
        break;
      case DepthUse::geometry:
      case DepthUse::write_mask:
        gl.Enable(GL_DEPTH_TEST);
        gl.DepthMask(GL_TRUE);  // also lets the depth clear through
        gl.DepthFunc(d.depth == DepthUse::geometry ? GL_LESS : GL_ALWAYS);
        gl.ClearBufferfv(GL_DEPTH, 0, d.depth == DepthUse::geometry ? &far_depth : &no_background);
        break;
      case DepthUse::skip_background:  // fullscreen triangle at depth 1.0; pixels holding 1.0 are not shaded
        gl.Enable(GL_DEPTH_TEST);
        gl.DepthMask(GL_FALSE);
        gl.DepthFunc(GL_NOTEQUAL);
        break;
    }
    for (const GlDraw::Clear& c : d.clears) gl.ClearBufferfv(GL_COLOR, c.location, c.value.data());
    gl.UseProgram(d.program);
    if (d.params) gl.BindBufferBase(GL_UNIFORM_BUFFER, shadergen::binding::kParams, d.params);
    // Every sampler unit at once; zeros unbind, so no stale texture can form a feedback loop with an attachment.
    gl.BindTextures(kFirstTextureUnit, kTextureUnits, d.units[parity].data());
    if (d.geometry) {
      gl.BindVertexArray(scene_vao_);
      if (index_count_ > 0) gl.DrawElements(GL_TRIANGLES, index_count_, GL_UNSIGNED_INT, nullptr);
    } else {
      gl.BindVertexArray(empty_vao_);
      gl.DrawArrays(GL_TRIANGLES, 0, 3);
    }
    gl.Finish();
    times[i] = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    // Outside the timed span; a flag read in Mesa, and it names the draw that failed.
    if (GLenum e = gl.GetError(); e != GL_NO_ERROR)
      throw BackendError(fmt::format("osmesa: GL error 0x{:04x} in draw {} of {}", e, d.name, p.variant_));
  }
  p.last_parity_ = parity;
  return times;
}

void OsmesaBackend::set_params(PreparedPipeline& pipeline, std::size_t draw, const std::vector<float>& params) {
  OsmesaPipeline& p = own(pipeline);
  if (draw >= p.draws_.size() || params.size() != p.draws_[draw].param_count)
    throw BackendError(fmt::format("osmesa: set_params: draw {} of {} takes {} floats, got {}", draw,
                                   p.draws_.size(), draw < p.draws_.size() ? p.draws_[draw].param_count : 0,
                                   params.size()));
  if (params.empty()) return;
  c_->make_current();
  // GL orders the update after the draws already issued that read the old block.
  c_->gl.NamedBufferSubData(p.draws_[draw].params, 0, GLsizeiptr(params.size() * sizeof(float)), params.data());
  c_->check("set_params of {}", p.variant_);
}

image::FloatImage OsmesaBackend::read_result(PreparedPipeline& pipeline) {
  OsmesaPipeline& p = own(pipeline);
  c_->make_current();
  GlFunctions& gl = c_->gl;
  if (p.last_parity_ < 0) throw BackendError("osmesa: read_result before render");
  GLuint tex = p.tex_[p.result_][p.last_parity_];
  Extent e = p.tex_size_[p.result_];
  image::FloatImage img;
  img.width = e.width;
  img.height = e.height;
  img.pixels.resize(std::size_t(e.width) * e.height);
  // Rows of floats are 4-byte aligned whatever the width; R32F -> GL_RED/GL_FLOAT is a plain copy, so NaN
  // and Inf survive, and row 0 is GL's bottom row (as FloatImage wants).
  gl.PixelStorei(GL_PACK_ALIGNMENT, 4);
  gl.GetTextureImage(tex, 0, GL_RED, GL_FLOAT, GLsizei(img.pixels.size() * sizeof(float)), img.pixels.data());
  c_->check("reading the result of {}", p.variant_);
  return img;
}

}  // namespace

std::unique_ptr<Backend> make_backend_with_version(const BackendOptions& options, int major, int minor) {
  return std::make_unique<OsmesaBackend>(options, major, minor);
}

GlNames object_names(const PreparedPipeline& pipeline) {
  const auto* p = dynamic_cast<const OsmesaPipeline*>(&pipeline);
  if (!p) throw std::invalid_argument("not an osmesa pipeline");
  return p->names_;
}

std::size_t count_live(Backend& backend, const GlNames& names) {
  auto* b = dynamic_cast<OsmesaBackend*>(&backend);
  if (!b) throw std::invalid_argument("not an osmesa backend");
  return b->count_live(names);
}

}  // namespace osmesa

std::unique_ptr<Backend> make_osmesa_backend(const BackendOptions& options) {
  return osmesa::make_backend_with_version(options, 4, 5);
}

}  // namespace aovar::render
