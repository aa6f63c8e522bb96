// DeviceInfo of a GL backend, and on OpenGL ES a measurement of what mediump does on the driver: the ES spec
// allows mediump to run in anything from fp16 up (GLSL ES 3.00 section 4.5.2), so it is measured, not assumed.
#include <array>

#include "render/gl/gl_context.h"

namespace aovar::render::gl {
namespace {

constexpr const char* kProbeVert =
    "#version 300 es\n"
    "void main() {\n"
    "  gl_Position = vec4(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0, 0.0, 1.0);\n"
    "}\n";
// 1 + 2^-12 (from gl_FragCoord, so no compiler folds it) in mediump (red) and in highp (green, the control):
// fp32 keeps the 2^-12, fp16 (10 mantissa bits) rounds it to 1.
constexpr const char* kProbeFrag =
    "#version 300 es\n"
    "precision highp float;\n"
    "layout(location = 0) out vec4 o;\n"
    "void main() {\n"
    "  mediump float m_step = gl_FragCoord.x * (1.0 / 2048.0);\n"
    "  mediump float m_sum = 1.0 + m_step;\n"
    "  highp float h_step = gl_FragCoord.x * (1.0 / 2048.0);\n"
    "  highp float h_sum = 1.0 + h_step;\n"
    "  o = vec4(m_sum, h_sum, 0.0, 1.0);\n"
    "}\n";

GLuint compile_probe(Context& c, GLenum stage, const char* source) {
  GLuint s = c.gl.CreateShader(stage);
  c.gl.ShaderSource(s, 1, &source, nullptr);
  c.gl.CompileShader(s);
  return s;
}

// The probe's one pixel (mediump sum, highp sum), negative when the driver could not run it.
std::array<float, 4> run_mediump_probe(Context& c) {
  Functions& gl = c.gl;
  GLuint vs = compile_probe(c, GL_VERTEX_SHADER, kProbeVert), fs = compile_probe(c, GL_FRAGMENT_SHADER, kProbeFrag);
  GLuint prog = gl.CreateProgram(), tex = 0, fbo = 0, vao = 0;
  gl.AttachShader(prog, vs);
  gl.AttachShader(prog, fs);
  gl.LinkProgram(prog);
  GLint linked = GL_FALSE;
  gl.GetProgramiv(prog, GL_LINK_STATUS, &linked);
  gl.GenTextures(1, &tex);
  gl.BindTexture(GL_TEXTURE_2D, tex);
  gl.TexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32F, 1, 1);
  gl.GenFramebuffers(1, &fbo);
  gl.BindFramebuffer(GL_FRAMEBUFFER, fbo);
  gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex, 0);
  gl.GenVertexArrays(1, &vao);
  std::array<float, 4> pixel{-1, -1, -1, -1};
  if (linked && gl.CheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE) {
    gl.Viewport(0, 0, 1, 1);
    gl.UseProgram(prog);
    gl.BindVertexArray(vao);
    gl.DrawArrays(GL_TRIANGLES, 0, 3);
    gl.ReadPixels(0, 0, 1, 1, GL_RGBA, GL_FLOAT, pixel.data());
  }
  gl.UseProgram(0);
  gl.BindVertexArray(0);
  gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
  gl.DeleteVertexArrays(1, &vao);
  gl.DeleteFramebuffers(1, &fbo);
  gl.DeleteTextures(1, &tex);
  gl.DeleteProgram(prog);
  gl.DeleteShader(vs);
  gl.DeleteShader(fs);
  c.check("while measuring mediump precision");
  return pixel;
}

void measure_precision(Context& c, DeviceInfo& info) {
  GLint range[2] = {0, 0}, bits = 0;
  c.gl.GetShaderPrecisionFormat(GL_FRAGMENT_SHADER, GL_MEDIUM_FLOAT, range, &bits);
  if (!c.has_extension("GL_EXT_color_buffer_float")) {
    info.precision = fmt::format("mediump not measured (no float render target); the driver reports {} "
                                 "mantissa bits for GL_MEDIUM_FLOAT", bits);
    return;
  }
  const auto [sum, control, unused_b, unused_a] = run_mediump_probe(c);
  const float fp32 = 1.0f + 1.0f / 4096.0f;
  info.ignores_relaxed_precision = sum == fp32 && control == fp32;
  if (control != fp32)
    info.precision = fmt::format("mediump not measured (the probe's highp control gave {}, not 1 + 2^-12); "
                                 "GL_MEDIUM_FLOAT reports {} mantissa bits", control, bits);
  else if (sum == fp32)
    info.precision = fmt::format("mediump runs in fp32 (measured: a mediump 1 + 2^-12 keeps its 2^-12; "
                                 "GL_MEDIUM_FLOAT reports {} mantissa bits)", bits);
  else if (sum == 1.0f)
    info.precision = fmt::format("mediump honoured (measured: a mediump 1 + 2^-12 rounds to 1 as fp16 does; "
                                 "GL_MEDIUM_FLOAT reports {} mantissa bits)", bits);
  else
    info.precision = fmt::format("mediump not measured (the probe's mediump 1 + 2^-12 gave {}); GL_MEDIUM_FLOAT "
                                 "reports {} mantissa bits", sum, bits);
}

}  // namespace

DeviceInfo describe(Context& c) {
  DeviceInfo info;
  const std::string version = c.string(GL_VERSION);  // "4.5 (Core Profile) Mesa 22.3.6", "OpenGL ES 3.2 Mesa 22.3.6"
  info.backend = c.setup.name;
  info.device = c.string(GL_RENDERER);
  info.api_version = c.setup.api_prefix + version;
  if (auto at = version.find("Mesa "); at != std::string::npos)
    info.driver = version.substr(at, version.find(' ', at + 5) - at);
  info.threads = c.setup.threads;
  if (c.setup.probe_mediump) {
    measure_precision(c, info);
  } else {
    // GLSL 4.50 section 4.7: precision qualifiers have no meaning in desktop GLSL, and llvmpipe runs fp32.
    info.ignores_relaxed_precision = true;
    info.precision = "mediump runs in fp32 (desktop GLSL ignores precision qualifiers)";
  }
  return info;
}

}  // namespace aovar::render::gl
