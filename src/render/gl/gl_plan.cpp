// The GL plan executor (gl_plan.h): a PipelinePlan into textures, FBOs and programs, rendered with a wall
// clock around state setup + draw + glFinish per draw: GL timer queries do not see llvmpipe's rasteriser
// threads (docs/architecture.md, "Rendering and timing"). Written against OpenGL ES 3.0, so no direct state
// access, texture views or glClearTexImage: objects are edited through bind points, a MIP level is read
// alone by narrowing the texture's base/max level for the draw, and textures are cleared through an FBO.
#include <algorithm>
#include <array>
#include <chrono>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "render/gbuffer_share.h"
#include "render/gl/gl_context.h"
#include "shadergen/bindings.h"

namespace aovar::render::gl {

std::size_t GlNames::size() const {
  return textures.size() + renderbuffers.size() + framebuffers.size() + buffers.size() + programs.size() +
         shaders.size();
}

namespace {

constexpr int kFirstTextureUnit = shadergen::binding::kFirstSampler;
constexpr int kTextureUnits = shadergen::binding::kSamplerCount;

GLenum internal_format(Format f) {
  switch (f) {
    case Format::r16f: return GL_R16F;
    case Format::r32f: return GL_R32F;
    case Format::rgba8: return GL_RGBA8;
    case Format::rg8: return GL_RG8;
    case Format::rgba32f: return GL_RGBA32F;
  }
  throw BackendError("gl: unknown texture format");
}

bool is_float(Format f) { return f == Format::r16f || f == Format::r32f || f == Format::rgba32f; }

float resolve_clear(float v, float far_plane) {
  if (v == kClearFar) return far_plane;
  if (v == kClearNegFar) return -far_plane;
  return v;
}

// A shader's or program's info log (glGetShaderInfoLog / glGetProgramInfoLog), up to 4 KiB.
template <class GetLog>
std::string info_log(GetLog get, GLuint object) {
  std::string log(4096, '\0');
  GLsizei n = 0;
  get(object, GLsizei(log.size()), &n, log.data());
  log.resize(std::max<GLsizei>(n, 0));
  return log;
}

// A texture on one sampler unit; a MIP chain read one level alone narrows base and max level to it.
struct Unit {
  GLuint texture = 0;
  GLint base = -1, max = -1;  // -1: single-level texture, leave its levels alone
};

// One draw of the plan with every GL name and value it needs, so the timed loop only issues GL calls.
struct GlDraw {
  std::string name;
  bool geometry = false;
  bool shared = false;  // the shared G-buffer's draw: render() draws that pipeline instead (gbuffer_share.h)
  DepthUse depth = DepthUse::none;
  Extent viewport;
  GLuint program = 0;
  GLuint params = 0;                                  // AOParams UBO, 0 = the draw has no block
  std::size_t param_count = 0;                        // floats in the block (set_params must match)
  std::array<GLuint, 2> fbo{};                        // by frame parity (the same FBO twice if it has none)
  std::array<std::array<Unit, kTextureUnits>, 2> units{};  // per sampler unit, by frame parity
  struct Clear {
    GLint location = 0;
    std::array<float, 4> raw{}, value{};  // raw may hold kClearFar / kClearNegFar; value is this frame's
  };
  std::vector<Clear> clears;  // colour attachments this draw clears first (it writes them first in a frame)
};

class GlPipeline final : public PreparedPipeline {
 public:
  GlPipeline(std::shared_ptr<Context> c, std::string variant) : c_(std::move(c)), variant_(std::move(variant)) {}

  ~GlPipeline() override {
    try {
      c_->make_current();
    } catch (const BackendError&) {
      return;  // the context is gone or unusable: its objects went with it
    }
    Functions& gl = c_->gl;
    gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
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
  // The shared G-buffer this pipeline reads, or null when it draws its own. Its textures and depth buffer are
  // lent: they are in tex_ and depth_buffers_ but not in names_, so this pipeline never deletes them.
  std::shared_ptr<SharedGbuffer> gbuffer_;
  std::vector<std::array<GLuint, 2>> tex_;  // per plan texture: copy by parity (equal when single)
  std::vector<GLuint> depth_buffers_;       // per plan depth buffer
  std::vector<Extent> tex_size_;
  std::vector<Format> tex_format_;
  GLuint frame_ubo_ = 0;
  std::vector<GlDraw> draws_;
  int result_ = -1;
  int last_parity_ = -1;  // parity of the last rendered frame, -1 before the first
};

// Binds a colour texture level to a scratch FBO, runs `use` on it and deletes the FBO: clearing a texture
// and reading one back, which ES 3.0 can only do through a framebuffer.
template <class F>
void with_scratch_framebuffer(Functions& gl, GLuint texture, F&& use) {
  GLuint fbo = 0;
  gl.GenFramebuffers(1, &fbo);
  gl.BindFramebuffer(GL_FRAMEBUFFER, fbo);
  gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture, 0);
  const GLenum attachment = GL_COLOR_ATTACHMENT0;
  gl.DrawBuffers(1, &attachment);
  gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
  use();
  gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
  gl.DeleteFramebuffers(1, &fbo);
}

class GlBackend final : public Backend {
 public:
  explicit GlBackend(std::shared_ptr<Context> c) : c_(std::move(c)), share_gbuffer_(c_->setup.share_gbuffer) {
    Functions& gl = c_->gl;
    info_ = describe(*c_);
    float_targets_ = !c_->setup.float_targets_need_extension || c_->has_extension("GL_EXT_color_buffer_float");
    // Fixed state: fullscreen triangles change winding with the y direction, and nothing blends.
    gl.Disable(GL_CULL_FACE);
    gl.Disable(GL_BLEND);
    gl.Disable(GL_SCISSOR_TEST);
    gl.Disable(GL_DITHER);
    gl.DepthFunc(GL_LESS);
    gl.GenVertexArrays(1, &empty_vao_);  // core profile draws need a VAO even without attributes
    gl.GenVertexArrays(1, &scene_vao_);
    c_->check("creating the context");
  }

  ~GlBackend() override {
    try {
      c_->make_current();
    } catch (const BackendError&) {
      return;
    }
    Functions& gl = c_->gl;
    gl.BindVertexArray(0);
    gl.DeleteVertexArrays(1, &empty_vao_);
    gl.DeleteVertexArrays(1, &scene_vao_);
    gl.DeleteBuffers(GLsizei(scene_buffers_.size()), scene_buffers_.data());
    gl.GetError();
  }

  const DeviceInfo& info() const override { return info_; }
  ClipDepth clip_depth() const override { return ClipDepth::minus_one_to_one; }  // no glClipControl in ES 3.0

  void set_scene(const scene::Scene& scene) override;
  std::unique_ptr<PreparedPipeline> prepare(const PipelinePlan& plan, Extent size) override;
  std::vector<double> render(PreparedPipeline& pipeline, const FrameSetup& frame) override;
  const void* shared_gbuffer(PreparedPipeline& pipeline) override { return own(pipeline).gbuffer_.get(); }
  double render_gbuffer(PreparedPipeline& pipeline, const FrameSetup& frame) override;
  std::size_t gbuffer_draws() const override { return gbuffer_draws_; }
  image::FloatImage read_result(PreparedPipeline& pipeline) override;
  void set_params(PreparedPipeline& pipeline, std::size_t draw, const std::vector<float>& params) override;

  std::size_t count_live(const GlNames& n) {
    c_->make_current();
    Functions& gl = c_->gl;
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
  const std::string& name() const { return c_->setup.name; }

  GlPipeline& own(PreparedPipeline& pipeline) {
    auto* p = dynamic_cast<GlPipeline*>(&pipeline);
    if (!p || p->c_ != c_) throw BackendError(name() + ": pipeline was prepared by another backend");
    return *p;
  }

  // Each shader compiled once, each (vertex, fragment) pair linked once, per prepare().
  struct Programs {
    std::map<int, GLuint> shaders;
    std::map<std::pair<int, int>, GLuint> linked;
  };

  // prepare() of the plan at its size; with `split`, the G-buffer is the pool's.
  std::unique_ptr<GlPipeline> prepare_at_size(const PipelinePlan& plan, Extent size, const GbufferSplit* split);
  // Draws p's shared G-buffer for `frame` when stale (always with `force`); returns its time.
  double ensure_gbuffer(GlPipeline& p, const FrameSetup& frame, bool force);
  // The steps of prepare(), in order; the GL objects go into the pipeline's names as they are created.
  void check_formats(const PipelinePlan& plan);
  void create_textures(const PipelinePlan& plan, const GbufferSplit* split, GlPipeline& p);
  void create_depth_buffers(const PipelinePlan& plan, const GbufferSplit* split, GlPipeline& p);
  GlDraw gl_draw(const PipelinePlan& plan, const Draw& d, GlPipeline& p, Programs& programs,
                 std::vector<bool>& written);
  GLuint program(const PipelinePlan& plan, const Draw& d, GlPipeline& p, Programs& programs);
  void bind_by_name(GLuint prog);
  GLuint compile(GlPipeline& p, const Shader& s);
  void upload_params(const Draw& d, GlPipeline& p, GlDraw& g);
  void bind_inputs(const PipelinePlan& plan, const Draw& d, GlPipeline& p, GlDraw& g);
  void create_framebuffers(const PipelinePlan& plan, const Draw& d, const std::vector<GLuint>& depth_buffers,
                           GlPipeline& p, GlDraw& g);
  void set_depth_state(DepthUse depth);
  void bind_units(const std::array<Unit, kTextureUnits>& units);

  std::shared_ptr<Context> c_;
  DeviceInfo info_;
  bool float_targets_ = true;
  GLuint empty_vao_ = 0, scene_vao_ = 0;
  std::array<GLuint, 3> scene_buffers_{};  // positions, normals, indices
  GLsizei index_count_ = 0;
  bool has_scene_ = false;
  std::uint64_t scene_generation_ = 0;  // of the uploaded scene (next_scene_generation)
  bool share_gbuffer_ = true;
  GbufferPool gbuffers_;
  std::size_t gbuffer_draws_ = 0;
};

void GlBackend::set_scene(const scene::Scene& scene) {
  // Check before touching the current scene, so a rejected one leaves the previous scene in place.
  if (scene.normals.size() != scene.positions.size())
    throw BackendError(fmt::format("{}: scene {} has {} normals for {} positions", name(), scene.name,
                                   scene.normals.size(), scene.positions.size()));
  if (scene.indices.size() % 3 != 0)
    throw BackendError(fmt::format("{}: scene {} has {} indices, not whole triangles", name(), scene.name,
                                   scene.indices.size()));
  for (std::uint32_t i : scene.indices)
    if (i >= scene.positions.size())
      throw BackendError(fmt::format("{}: scene {} indexes vertex {} of {}", name(), scene.name, i,
                                     scene.positions.size()));
  c_->make_current();
  Functions& gl = c_->gl;
  gl.BindVertexArray(0);
  gl.DeleteBuffers(GLsizei(scene_buffers_.size()), scene_buffers_.data());
  scene_buffers_ = {};
  index_count_ = 0;
  gl.GenBuffers(3, scene_buffers_.data());
  gl.BindVertexArray(scene_vao_);  // the element buffer binding is VAO state
  auto store = [&](GLenum target, GLuint buffer, std::size_t bytes, const void* data) {
    gl.BindBuffer(target, buffer);
    gl.BufferData(target, GLsizeiptr(bytes), bytes ? data : nullptr, GL_STATIC_DRAW);
  };
  store(GL_ARRAY_BUFFER, scene_buffers_[0], scene.positions.size() * sizeof(glm::vec3), scene.positions.data());
  gl.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(glm::vec3), nullptr);  // a_position
  store(GL_ARRAY_BUFFER, scene_buffers_[1], scene.normals.size() * sizeof(glm::vec3), scene.normals.data());
  gl.VertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(glm::vec3), nullptr);  // a_normal
  gl.EnableVertexAttribArray(0);
  gl.EnableVertexAttribArray(1);
  store(GL_ELEMENT_ARRAY_BUFFER, scene_buffers_[2], scene.indices.size() * sizeof(std::uint32_t),
        scene.indices.data());
  gl.BindVertexArray(0);
  gl.BindBuffer(GL_ARRAY_BUFFER, 0);
  index_count_ = GLsizei(scene.indices.size());
  has_scene_ = true;
  scene_generation_ = next_scene_generation();
  c_->check("uploading scene {}", scene.name);
}

std::unique_ptr<PreparedPipeline> GlBackend::prepare(const PipelinePlan& full_plan, Extent size) {
  const PipelinePlan plan = plan_for_size(full_plan, size);
  const auto split = share_gbuffer_ ? split_gbuffer(plan, size) : std::nullopt;
  return prepare_at_size(plan, size, split ? &*split : nullptr);
}

std::unique_ptr<GlPipeline> GlBackend::prepare_at_size(const PipelinePlan& plan, Extent size,
                                                       const GbufferSplit* split) {
  auto start = std::chrono::steady_clock::now();
  c_->make_current();
  Functions& gl = c_->gl;
  c_->check("before prepare");
  if (size.width <= 0 || size.height <= 0)
    throw BackendError(fmt::format("{}: invalid output size {}x{}", name(), size.width, size.height));
  validate_plan(plan, name());
  for (const Draw& d : plan.draws)
    if (d.trace_words > 0)
      throw BackendError(fmt::format("{}: draw {} of {} is a trace build, which runs on {} only", name(),
                                     d.name, plan.variant, backend_for(variants::Target::vulkan)));
  check_formats(plan);
  // Built inside the pipeline object so that a throw part-way deletes what was already created.
  auto p = std::make_unique<GlPipeline>(c_, plan.variant);
  p->size_ = size;
  p->ao_ = ao_extent(size, plan.resolution);
  p->result_ = plan.result;
  if (split)  // the pool's G-buffer, prepared on first use; its textures and depth buffer are lent below
    p->gbuffer_ = gbuffers_.get(*split, size, [&](const PipelinePlan& g) { return prepare_at_size(g, size, nullptr); });

  create_textures(plan, split, *p);
  create_depth_buffers(plan, split, *p);
  // AOFrame, filled by render.
  gl.GenBuffers(1, &p->frame_ubo_);
  p->names_.buffers.push_back(p->frame_ubo_);
  gl.BindBuffer(GL_UNIFORM_BUFFER, p->frame_ubo_);
  gl.BufferData(GL_UNIFORM_BUFFER, sizeof(FrameBlock), nullptr, GL_DYNAMIC_DRAW);
  Programs programs;
  std::vector<bool> written(plan.textures.size(), false);  // by a draw before this one
  for (std::size_t i = 0; i < plan.draws.size(); ++i) {
    if (split && i == split->draw) {  // drawn by the shared G-buffer's own pipeline
      GlDraw shared;
      shared.name = plan.draws[i].name;
      shared.geometry = shared.shared = true;
      for (const TextureRef& o : plan.draws[i].outputs)
        if (o.texture >= 0) written[o.texture] = true;
      p->draws_.push_back(std::move(shared));
      continue;
    }
    p->draws_.push_back(gl_draw(plan, plan.draws[i], *p, programs, written));
  }

  // Shaders are owned by their programs once linked.
  for (GLuint s : p->live_shaders_) gl.DeleteShader(s);
  p->live_shaders_.clear();
  gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
  c_->check("while preparing {}", plan.variant);
  p->create_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return p;
}

// OpenGL ES renders into float textures only with EXT_color_buffer_float; say so before creating anything.
void GlBackend::check_formats(const PipelinePlan& plan) {
  if (float_targets_) return;
  for (const Texture& t : plan.textures)
    if (is_float(t.format))
      throw BackendError(fmt::format(
          "{}: {} renders into a {} texture ({}), but the driver lacks GL_EXT_color_buffer_float (float render "
          "targets; Mesa's llvmpipe has it: {})", name(), plan.variant, format_name(t.format), t.name,
          c_->setup.install));
}

// Textures: double-buffered ones start open (1.0) so that frame 0 reads a defined history. Those of a shared
// G-buffer are its pipeline's.
void GlBackend::create_textures(const PipelinePlan& plan, const GbufferSplit* split, GlPipeline& p) {
  Functions& gl = c_->gl;
  for (std::size_t i = 0; i < plan.textures.size(); ++i) {
    const Texture& t = plan.textures[i];
    Extent e = t.full_resolution ? p.size_ : p.ao_;
    if (split && split->texture[i] >= 0) {
      p.tex_.push_back(static_cast<const GlPipeline&>(*p.gbuffer_->pipeline).tex_.at(split->texture[i]));
      p.tex_size_.push_back(e);
      p.tex_format_.push_back(t.format);
      continue;
    }
    std::array<GLuint, 2> copies{};
    int n = t.double_buffered ? 2 : 1;
    gl.GenTextures(n, copies.data());
    for (int i = 0; i < n; ++i) {
      p.names_.textures.push_back(copies[i]);
      gl.BindTexture(GL_TEXTURE_2D, copies[i]);
      gl.TexStorage2D(GL_TEXTURE_2D, std::max(t.levels, 1), internal_format(t.format), e.width, e.height);
      // Every read is a texelFetch; a mipmapped filter keeps levels > 0 inside the texture's level range.
      gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, t.levels > 1 ? GL_NEAREST_MIPMAP_NEAREST : GL_NEAREST);
      gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
      gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
      gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
      if (t.double_buffered) {
        const float one[4] = {1, 1, 1, 1};
        with_scratch_framebuffer(gl, copies[i], [&] { gl.ClearBufferfv(GL_COLOR, 0, one); });
      }
    }
    gl.BindTexture(GL_TEXTURE_2D, 0);
    if (n == 1) copies[1] = copies[0];
    p.tex_.push_back(copies);
    p.tex_size_.push_back(e);
    p.tex_format_.push_back(t.format);
  }
}

// Depth buffers: the G-buffer's (a shared G-buffer's is its pipeline's), the background mask (plan.h).
void GlBackend::create_depth_buffers(const PipelinePlan& plan, const GbufferSplit* split, GlPipeline& p) {
  Functions& gl = c_->gl;
  std::vector<GLuint>& buffers = p.depth_buffers_;
  for (std::size_t i = 0; i < plan.depth_buffers.size(); ++i) {
    const DepthBuffer& b = plan.depth_buffers[i];
    if (split && split->depth_buffer == static_cast<int>(i)) {
      buffers.push_back(static_cast<const GlPipeline&>(*p.gbuffer_->pipeline).depth_buffers_.at(0));
      continue;
    }
    GLuint rb = 0;
    gl.GenRenderbuffers(1, &rb);
    p.names_.renderbuffers.push_back(rb);
    const Extent e = b.full_resolution ? p.size_ : p.ao_;
    gl.BindRenderbuffer(GL_RENDERBUFFER, rb);
    gl.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, e.width, e.height);
    buffers.push_back(rb);
  }
  gl.BindRenderbuffer(GL_RENDERBUFFER, 0);
}

// Draw `d` with every GL name it needs. `written` marks the textures earlier draws wrote: the first draw
// to write a texture clears it when the texture asks for a clear.
GlDraw GlBackend::gl_draw(const PipelinePlan& plan, const Draw& d, GlPipeline& p, Programs& programs,
                          std::vector<bool>& written) {
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
  create_framebuffers(plan, d, p.depth_buffers_, p, g);
  for (std::size_t loc = 0; loc < d.outputs.size(); ++loc) {
    int t = d.outputs[loc].texture;
    if (t < 0 || written[t]) continue;
    written[t] = true;
    if (plan.textures[t].cleared) g.clears.push_back({GLint(loc), plan.textures[t].clear, plan.textures[t].clear});
  }
  return g;
}

GLuint GlBackend::program(const PipelinePlan& plan, const Draw& d, GlPipeline& p, Programs& programs) {
  auto key = std::make_pair(d.vertex, d.fragment);
  if (auto it = programs.linked.find(key); it != programs.linked.end()) return it->second;
  auto shader = [&](int index) {
    auto it = programs.shaders.find(index);
    if (it == programs.shaders.end()) it = programs.shaders.emplace(index, compile(p, plan.shaders[index])).first;
    return it->second;
  };
  Functions& gl = c_->gl;
  GLuint vs = shader(d.vertex), fs = shader(d.fragment);
  GLuint prog = gl.CreateProgram();
  p.names_.programs.push_back(prog);
  gl.AttachShader(prog, vs);
  gl.AttachShader(prog, fs);
  // GLSL ES 3.00 has vertex input locations, but a template may leave them to the renderer.
  gl.BindAttribLocation(prog, 0, "a_position");
  gl.BindAttribLocation(prog, 1, "a_normal");
  gl.LinkProgram(prog);
  gl.DetachShader(prog, vs);
  gl.DetachShader(prog, fs);
  GLint ok = GL_FALSE;
  gl.GetProgramiv(prog, GL_LINK_STATUS, &ok);
  if (!ok) {
    const std::string log = info_log(gl.GetProgramInfoLog, prog);
    throw BackendError(fmt::format("{}: {} + {} ({}): GLSL link failed: {}", name(),
                                   plan.shaders[d.vertex].program_key, plan.shaders[d.fragment].program_key,
                                   plan.variant, one_line(log)));
  }
  bind_by_name(prog);
  programs.linked.emplace(key, prog);
  return prog;
}

// The template contract's bindings by name (GLSL ES 3.00 has no binding qualifiers; on GL 4.5 this
// restates what the qualifiers already set). Names a program does not use are skipped.
void GlBackend::bind_by_name(GLuint prog) {
  Functions& gl = c_->gl;
  for (int b : {shadergen::binding::kFrame, shadergen::binding::kParams})
    if (GLuint index = gl.GetUniformBlockIndex(prog, shadergen::binding::name(b)); index != GL_INVALID_INDEX)
      gl.UniformBlockBinding(prog, index, GLuint(b));
  gl.UseProgram(prog);
  for (int b = shadergen::binding::kFirstSampler; b < shadergen::binding::kCount; ++b)
    if (GLint loc = gl.GetUniformLocation(prog, shadergen::binding::name(b)); loc >= 0) gl.Uniform1i(loc, b);
  gl.UseProgram(0);
}

GLuint GlBackend::compile(GlPipeline& p, const Shader& s) {
  Functions& gl = c_->gl;
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
    const std::string log = info_log(gl.GetShaderInfoLog, shader);
    // Mesa's log says "<source>:<line>(<column>)", the template file and line of the #line directives.
    throw BackendError(fmt::format("{}: {} ({}): GLSL compile failed: {}", name(), s.program_key, p.variant_,
                                   s.glsl.empty() ? fmt::format("no GLSL source (was the {} target compiled?)",
                                                                c_->setup.glsl_target)
                                                  : one_line(log)));
  }
  return shader;
}

// The draw's AOParams block, when it has one. std140: consecutive floats at 4 * i; the block's size
// rounds up to a vec4.
void GlBackend::upload_params(const Draw& d, GlPipeline& p, GlDraw& g) {
  if (d.params.empty()) return;
  Functions& gl = c_->gl;
  std::vector<float> block((d.params.size() + 3) / 4 * 4, 0.0f);
  std::copy(d.params.begin(), d.params.end(), block.begin());
  gl.GenBuffers(1, &g.params);
  p.names_.buffers.push_back(g.params);
  gl.BindBuffer(GL_UNIFORM_BUFFER, g.params);
  gl.BufferData(GL_UNIFORM_BUFFER, GLsizeiptr(block.size() * sizeof(float)), block.data(), GL_DYNAMIC_DRAW);
  g.param_count = d.params.size();
}

// Inputs by parity: at parity q the current copy of a double-buffered texture is q, the previous 1 - q. A
// MIP chain is read whole or one level alone (as level 0: texelFetch's lod counts from the base level).
void GlBackend::bind_inputs(const PipelinePlan& plan, const Draw& d, GlPipeline& p, GlDraw& g) {
  for (const auto& [binding, ref] : d.inputs) {
    const int unit = binding - kFirstTextureUnit;
    const int levels = std::max(plan.textures[ref.texture].levels, 1);
    for (int q = 0; q < 2; ++q) {
      Unit& u = g.units[q][unit];
      u.texture = p.tex_[ref.texture][ref.previous ? 1 - q : q];
      if (levels > 1) {
        u.base = ref.level < 0 ? 0 : ref.level;
        u.max = ref.level < 0 ? levels - 1 : ref.level;
      }
    }
  }
  for (int q = 0; q < 2; ++q)  // one texture on two units would need two level ranges at once
    for (int a = 0; a < kTextureUnits; ++a)
      for (int b = a + 1; b < kTextureUnits; ++b) {
        const Unit &ua = g.units[q][a], &ub = g.units[q][b];
        if (ua.texture && ua.texture == ub.texture && (ua.base != ub.base || ua.max != ub.max))
          throw BackendError(fmt::format("{}: {}: draw {} reads one texture at two MIP ranges", name(),
                                         plan.variant, d.name));
      }
}

// Framebuffers: location i -> GL_COLOR_ATTACHMENTi (GL_NONE where the plan leaves a location unused); one
// per parity when the draw writes a double-buffered texture.
void GlBackend::create_framebuffers(const PipelinePlan& plan, const Draw& d, const std::vector<GLuint>& depth_buffers,
                                    GlPipeline& p, GlDraw& g) {
  Functions& gl = c_->gl;
  bool parity_dependent = false;
  for (const TextureRef& r : d.outputs)
    if (r.texture >= 0) parity_dependent |= plan.textures[r.texture].double_buffered;
  std::vector<GLenum> buffers(d.outputs.size(), GL_NONE);
  for (int q = 0; q < (parity_dependent ? 2 : 1); ++q) {
    GLuint fbo = 0;
    gl.GenFramebuffers(1, &fbo);
    p.names_.framebuffers.push_back(fbo);
    gl.BindFramebuffer(GL_FRAMEBUFFER, fbo);
    for (std::size_t loc = 0; loc < d.outputs.size(); ++loc) {
      const TextureRef& r = d.outputs[loc];
      if (r.texture < 0) continue;
      gl.FramebufferTexture2D(GL_FRAMEBUFFER, GLenum(GL_COLOR_ATTACHMENT0 + loc), GL_TEXTURE_2D,
                              p.tex_[r.texture][q], std::max(r.level, 0));
      buffers[loc] = GLenum(GL_COLOR_ATTACHMENT0 + loc);
    }
    if (d.depth_buffer >= 0)
      gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_buffers[d.depth_buffer]);
    gl.DrawBuffers(GLsizei(buffers.size()), buffers.data());
    GLenum status = gl.CheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
      throw BackendError(fmt::format("{}: {}: framebuffer of draw {} is incomplete (status 0x{:04x})", name(),
                                     plan.variant, d.name, status));
    g.fbo[q] = fbo;
  }
  if (!parity_dependent) g.fbo[1] = g.fbo[0];
}

void GlBackend::set_depth_state(DepthUse depth) {
  Functions& gl = c_->gl;
  const float far_depth = 1.0f, no_background = 0.0f;
  switch (depth) {
    case DepthUse::none:
      gl.Disable(GL_DEPTH_TEST);
      gl.DepthMask(GL_FALSE);
      break;
    case DepthUse::geometry:
    case DepthUse::write_mask:
      gl.Enable(GL_DEPTH_TEST);
      gl.DepthMask(GL_TRUE);  // also lets the depth clear through
      gl.DepthFunc(depth == DepthUse::geometry ? GL_LESS : GL_ALWAYS);
      gl.ClearBufferfv(GL_DEPTH, 0, depth == DepthUse::geometry ? &far_depth : &no_background);
      break;
    case DepthUse::skip_background:  // fullscreen triangle at depth 1.0; pixels holding 1.0 are not shaded
      gl.Enable(GL_DEPTH_TEST);
      gl.DepthMask(GL_FALSE);
      gl.DepthFunc(GL_NOTEQUAL);
      break;
  }
}

// Every sampler unit; zeros unbind, so no stale texture can form a feedback loop with an attachment.
void GlBackend::bind_units(const std::array<Unit, kTextureUnits>& units) {
  Functions& gl = c_->gl;
  for (int u = 0; u < kTextureUnits; ++u) {
    gl.ActiveTexture(GLenum(GL_TEXTURE0 + kFirstTextureUnit + u));
    gl.BindTexture(GL_TEXTURE_2D, units[u].texture);
    if (units[u].base < 0) continue;
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_BASE_LEVEL, units[u].base);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, units[u].max);
  }
}

std::vector<double> GlBackend::render(PreparedPipeline& pipeline, const FrameSetup& frame) {
  GlPipeline& p = own(pipeline);
  c_->make_current();
  Functions& gl = c_->gl;
  if (!frame.view) throw BackendError(name() + ": render without a view");
  bool geometry = std::any_of(p.draws_.begin(), p.draws_.end(), [](const GlDraw& d) { return d.geometry; });
  if (geometry && !has_scene_) throw BackendError(name() + ": render before set_scene");
  if (p.gbuffer_) ensure_gbuffer(p, frame, false);

  FrameBlock block = make_frame_block(frame, p.size_, p.ao_, ClipDepth::minus_one_to_one);
  gl.BindBuffer(GL_UNIFORM_BUFFER, p.frame_ubo_);
  gl.BufferSubData(GL_UNIFORM_BUFFER, 0, sizeof block, &block);
  gl.BindBufferBase(GL_UNIFORM_BUFFER, shadergen::binding::kFrame, p.frame_ubo_);
  for (GlDraw& d : p.draws_)
    for (GlDraw::Clear& c : d.clears)
      for (int i = 0; i < 4; ++i) c.value[i] = resolve_clear(c.raw[i], background_depth(frame.view->far_plane));
  const int parity = frame.frame & 1;
  std::vector<double> times(p.draws_.size(), 0.0);
  c_->check("before the first draw of {}", p.variant_);
  gl.Finish();  // earlier work (uploads, the previous frame) must not land in the first draw's time

  for (std::size_t i = 0; i < p.draws_.size(); ++i) {
    const GlDraw& d = p.draws_[i];
    if (d.shared) {  // drawn above when stale: the time of the draw this frame reads
      times[i] = p.gbuffer_->last_ms;
      continue;
    }
    if (d.geometry) ++gbuffer_draws_;
    auto t0 = std::chrono::steady_clock::now();
    gl.BindFramebuffer(GL_DRAW_FRAMEBUFFER, d.fbo[parity]);
    gl.Viewport(0, 0, d.viewport.width, d.viewport.height);
    set_depth_state(d.depth);
    for (const GlDraw::Clear& c : d.clears) gl.ClearBufferfv(GL_COLOR, c.location, c.value.data());
    gl.UseProgram(d.program);
    if (d.params) gl.BindBufferBase(GL_UNIFORM_BUFFER, shadergen::binding::kParams, d.params);
    bind_units(d.units[parity]);
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
      throw BackendError(fmt::format("{}: GL error 0x{:04x} in draw {} of {}", name(), e, d.name, p.variant_));
  }
  p.last_parity_ = parity;
  return times;
}

double GlBackend::ensure_gbuffer(GlPipeline& p, const FrameSetup& frame, bool force) {
  const FrameBlock block = make_frame_block(frame, p.size_, p.ao_, ClipDepth::minus_one_to_one);
  // No store: a GL G-buffer is drawn every time it is stale (render/gbuffer_share.h keeps Vulkan's only).
  const GbufferOps ops{[&](PreparedPipeline& g) { return render(g, frame); }, nullptr, nullptr};
  return gbuffers_.ensure(*p.gbuffer_, gbuffer_content(block, scene_generation_), block, force, ops);
}

double GlBackend::render_gbuffer(PreparedPipeline& pipeline, const FrameSetup& frame) {
  GlPipeline& p = own(pipeline);
  if (!p.gbuffer_) return Backend::render_gbuffer(pipeline, frame);
  if (!frame.view) throw BackendError(name() + ": render_gbuffer without a view");
  if (!has_scene_) throw BackendError(name() + ": render_gbuffer before set_scene");
  return ensure_gbuffer(p, frame, true);
}

void GlBackend::set_params(PreparedPipeline& pipeline, std::size_t draw, const std::vector<float>& params) {
  GlPipeline& p = own(pipeline);
  if (draw >= p.draws_.size() || params.size() != p.draws_[draw].param_count)
    throw BackendError(fmt::format("{}: set_params: draw {} of {} takes {} floats, got {}", name(), draw,
                                   p.draws_.size(), draw < p.draws_.size() ? p.draws_[draw].param_count : 0,
                                   params.size()));
  if (params.empty()) return;
  c_->make_current();
  // GL orders the update after the draws already issued that read the old block.
  c_->gl.BindBuffer(GL_UNIFORM_BUFFER, p.draws_[draw].params);
  c_->gl.BufferSubData(GL_UNIFORM_BUFFER, 0, GLsizeiptr(params.size() * sizeof(float)), params.data());
  c_->check("set_params of {}", p.variant_);
}

image::FloatImage GlBackend::read_result(PreparedPipeline& pipeline) {
  GlPipeline& p = own(pipeline);
  c_->make_current();
  Functions& gl = c_->gl;
  if (p.last_parity_ < 0) throw BackendError(name() + ": read_result before render");
  if (p.result_ < 0) throw BackendError(name() + ": read_result of a G-buffer, which has no result");
  const GLuint tex = p.tex_[p.result_][p.last_parity_];
  const Extent e = p.tex_size_[p.result_];
  const bool fixed_point = !is_float(p.tex_format_[p.result_]);
  image::FloatImage img;
  img.width = e.width;
  img.height = e.height;
  img.pixels.resize(std::size_t(e.width) * e.height);
  // ES 3.0 reads a float colour buffer as RGBA/FLOAT and a normalised one as RGBA/UNSIGNED_BYTE (section
  // 4.3.2). Float to float is a plain copy, so NaN and Inf survive; row 0 is GL's bottom row (as FloatImage wants).
  std::vector<float> rgba(fixed_point ? 0 : img.pixels.size() * 4);
  std::vector<unsigned char> bytes(fixed_point ? img.pixels.size() * 4 : 0);
  gl.PixelStorei(GL_PACK_ALIGNMENT, 4);
  with_scratch_framebuffer(gl, tex, [&] {
    if (fixed_point) gl.ReadPixels(0, 0, e.width, e.height, GL_RGBA, GL_UNSIGNED_BYTE, bytes.data());
    else gl.ReadPixels(0, 0, e.width, e.height, GL_RGBA, GL_FLOAT, rgba.data());
  });
  for (std::size_t i = 0; i < img.pixels.size(); ++i)
    img.pixels[i] = fixed_point ? float(bytes[4 * i]) / 255.0f : rgba[4 * i];
  c_->check("reading the result of {}", p.variant_);
  return img;
}

}  // namespace

std::unique_ptr<Backend> make_backend(std::unique_ptr<Platform> platform, const Setup& setup) {
  return std::make_unique<GlBackend>(std::make_shared<Context>(std::move(platform), setup));
}

GlNames object_names(const PreparedPipeline& pipeline) {
  const auto* p = dynamic_cast<const GlPipeline*>(&pipeline);
  if (!p) throw std::invalid_argument("not a GL pipeline");
  return p->names_;
}

std::size_t count_live(Backend& backend, const GlNames& names) {
  auto* b = dynamic_cast<GlBackend*>(&backend);
  if (!b) throw std::invalid_argument("not a GL backend");
  return b->count_live(names);
}

}  // namespace aovar::render::gl
