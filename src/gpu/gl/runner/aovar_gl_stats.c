/* aovar-gl-stats: compiles many vertex + fragment programs in one OpenGL ES 3 context on a drm-shim render
 * node and prints what the driver's compiler reports through KHR_debug, as Mesa's shader-db runner does.
 * aovar execs it (gpu/gl/compiler.h): LD_PRELOAD of the noop shim cannot reach a forked child, and batching
 * pays the driver's (and under qemu-user the emulator's) start-up once for many programs.
 *
 * Usage: aovar-gl-stats LIST, where LIST has one program a line: "<id>\t<vertex file>\t<fragment file>".
 * Output, one record a line, tab-separated, flushed after each program:
 *   renderer <GL_RENDERER>     version <GL_VERSION>          (once, first)
 *   begin <id>                 msg <one line of a compiler message>        ...
 *   end <id>  |  fail <id> <the compile or link log, on one line>
 * A driver crash ends the process; the caller restarts it after the last "begin".
 *
 * Written in C against dlopen'ed libEGL/libgbm with the few EGL/GL declarations it needs (below), so that one
 * source builds natively and with Debian's aarch64 cross compiler without arm64 development packages. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <fcntl.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

typedef void *EGLDisplay, *EGLContext, *EGLConfig, *EGLSurface;
typedef int32_t EGLint;
typedef unsigned EGLenum, EGLBoolean;
typedef unsigned GLenum, GLuint;
typedef int GLint, GLsizei;
typedef unsigned char GLboolean;
typedef char GLchar;
#define EGL_PLATFORM_GBM_MESA 0x31D7
#define EGL_OPENGL_ES_API 0x30A0
#define EGL_CONTEXT_CLIENT_VERSION 0x3098
#define EGL_NONE 0x3038
#define GL_RENDERER 0x1F01
#define GL_VERSION 0x1F02
#define GL_DEBUG_OUTPUT 0x92E0
#define GL_DEBUG_OUTPUT_SYNCHRONOUS 0x8242
#define GL_DEBUG_SOURCE_SHADER_COMPILER 0x8248
#define GL_DEBUG_TYPE_OTHER 0x8251
#define GL_DONT_CARE 0x1100
#define GL_VERTEX_SHADER 0x8B31
#define GL_FRAGMENT_SHADER 0x8B30
#define GL_COMPILE_STATUS 0x8B81
#define GL_LINK_STATUS 0x8B82
#define GL_FALSE 0
#define GL_TRUE 1

typedef void (*DebugProc)(GLenum, GLenum, GLuint, GLenum, GLsizei, const GLchar *, const void *);
static struct {
  void *(*GetProcAddress)(const char *);
  EGLDisplay (*GetPlatformDisplay)(EGLenum, void *, const EGLint *);
  EGLBoolean (*Initialize)(EGLDisplay, EGLint *, EGLint *);
  EGLBoolean (*BindAPI)(EGLenum);
  EGLContext (*CreateContext)(EGLDisplay, EGLConfig, EGLContext, const EGLint *);
  EGLBoolean (*MakeCurrent)(EGLDisplay, EGLSurface, EGLSurface, EGLContext);
  EGLint (*GetError)(void);
} egl;
static struct {
  const char *(*GetString)(GLenum);
  void (*Enable)(GLenum);
  void (*DebugMessageControl)(GLenum, GLenum, GLenum, GLsizei, const GLuint *, GLboolean);
  void (*DebugMessageCallback)(DebugProc, const void *);
  GLuint (*CreateShader)(GLenum);
  void (*ShaderSource)(GLuint, GLsizei, const GLchar *const *, const GLint *);
  void (*CompileShader)(GLuint);
  void (*GetShaderiv)(GLuint, GLenum, GLint *);
  void (*GetShaderInfoLog)(GLuint, GLsizei, GLsizei *, GLchar *);
  void (*DeleteShader)(GLuint);
  GLuint (*CreateProgram)(void);
  void (*AttachShader)(GLuint, GLuint);
  void (*LinkProgram)(GLuint);
  void (*GetProgramiv)(GLuint, GLenum, GLint *);
  void (*GetProgramInfoLog)(GLuint, GLsizei, GLsizei *, GLchar *);
  void (*DeleteProgram)(GLuint);
} gl;

static void die(const char *what) {
  fprintf(stderr, "aovar-gl-stats: %s\n", what);
  exit(2);
}

/* Prints `text` as one record: newlines and tabs become spaces. */
static void print_flat(const char *tag, const char *id, const char *text, size_t len) {
  fputs(tag, stdout);
  if (id) printf("\t%s", id);
  putchar('\t');
  for (size_t i = 0; i < len && text[i]; ++i) putchar(text[i] == '\n' || text[i] == '\t' || text[i] == '\r' ? ' ' : text[i]);
  putchar('\n');
}

/* Each line of a compiler message is its own record (Intel's and freedreno's reports span lines). */
static void on_message(GLenum source, GLenum type, GLuint id, GLenum severity, GLsizei length, const GLchar *message,
                       const void *user) {
  (void)source, (void)type, (void)id, (void)severity, (void)user;
  const char *p = message, *end = message + (length > 0 ? (size_t)length : strlen(message));
  while (p < end) {
    const char *nl = memchr(p, '\n', (size_t)(end - p));
    const char *stop = nl ? nl : end;
    if (stop > p) print_flat("msg", NULL, p, (size_t)(stop - p));
    p = stop + 1;
  }
}

static void *need(void *lib, const char *name) {
  void *f = lib ? dlsym(lib, name) : NULL;
  if (!f && egl.GetProcAddress) f = egl.GetProcAddress(name);
  if (!f) {
    char what[256];
    snprintf(what, sizeof what, "missing entry point %s", name);
    die(what);
  }
  return f;
}

static void load_gl(void) {
#define GL(n) *(void **)&gl.n = need(NULL, "gl" #n)
  GL(GetString); GL(Enable); GL(DebugMessageControl); GL(DebugMessageCallback); GL(CreateShader);
  GL(ShaderSource); GL(CompileShader); GL(GetShaderiv); GL(GetShaderInfoLog); GL(DeleteShader);
  GL(CreateProgram); GL(AttachShader); GL(LinkProgram); GL(GetProgramiv); GL(GetProgramInfoLog); GL(DeleteProgram);
#undef GL
}

/* An OpenGL ES 3 context on the (shimmed) render node through GBM, no surface. */
static void open_context(void) {
  void *libegl = dlopen("libEGL.so.1", RTLD_NOW | RTLD_GLOBAL), *libgbm = dlopen("libgbm.so.1", RTLD_NOW | RTLD_GLOBAL);
  if (!libegl || !libgbm) die(dlerror());
  *(void **)&egl.GetProcAddress = need(libegl, "eglGetProcAddress");
#define EGL(n) *(void **)&egl.n = need(libegl, "egl" #n)
  EGL(GetPlatformDisplay); EGL(Initialize); EGL(BindAPI); EGL(CreateContext); EGL(MakeCurrent); EGL(GetError);
#undef EGL
  void *(*create_device)(int) = (void *(*)(int))need(libgbm, "gbm_create_device");
  const char *node = getenv("AOVAR_RENDER_NODE") ? getenv("AOVAR_RENDER_NODE") : "/dev/dri/renderD128";
  int fd = open(node, O_RDWR);
  if (fd < 0) die("cannot open the render node (is the drm-shim preloaded?)");
  void *gbm = create_device(fd);
  if (!gbm) die("gbm_create_device failed");
  EGLDisplay display = egl.GetPlatformDisplay(EGL_PLATFORM_GBM_MESA, gbm, NULL);
  EGLint major, minor;
  if (!display || !egl.Initialize(display, &major, &minor)) die("eglInitialize failed");
  egl.BindAPI(EGL_OPENGL_ES_API);
  const EGLint attributes[] = {EGL_CONTEXT_CLIENT_VERSION, 3, EGL_NONE};
  EGLContext context = egl.CreateContext(display, NULL, NULL, attributes);
  if (!context) die("eglCreateContext (OpenGL ES 3) failed");
  if (!egl.MakeCurrent(display, NULL, NULL, context)) die("eglMakeCurrent failed");
  load_gl();
}

static char *slurp(const char *path) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  fseek(f, 0, SEEK_END);
  long n = ftell(f);
  rewind(f);
  char *text = malloc((size_t)n + 1);
  if (text && fread(text, 1, (size_t)n, f) != (size_t)n) n = 0;
  if (text) text[n] = 0;
  fclose(f);
  return text;
}

/* Compiles one shader; on failure prints the "fail" record and returns 0. */
static GLuint compile(const char *id, GLenum stage, const char *path) {
  char *source = slurp(path);
  if (!source) {
    printf("fail\t%s\tcannot read %s\n", id, path);
    return 0;
  }
  GLuint shader = gl.CreateShader(stage);
  gl.ShaderSource(shader, 1, (const GLchar *const *)&source, NULL);
  gl.CompileShader(shader);
  free(source);
  GLint ok = 0;
  gl.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok) return shader;
  char log[4096] = "";
  gl.GetShaderInfoLog(shader, sizeof log, NULL, log);
  print_flat("fail", id, log, sizeof log);
  gl.DeleteShader(shader);
  return 0;
}

/* One program: compile both stages and link (the statistics come from the link: ST_DEBUG=precompile). */
static void run_program(const char *id, const char *vertex, const char *fragment) {
  printf("begin\t%s\n", id);
  fflush(stdout);
  /* Test hook: a driver crash on this program (tests/gpu/test_gl_chips.cpp). */
  const char *crash = getenv("AOVAR_GL_STATS_TEST_CRASH");
  if (crash && !strcmp(crash, id)) raise(SIGSEGV);
  GLuint vs = compile(id, GL_VERTEX_SHADER, vertex), fs = vs ? compile(id, GL_FRAGMENT_SHADER, fragment) : 0;
  if (vs && fs) {
    GLuint program = gl.CreateProgram();
    gl.AttachShader(program, vs);
    gl.AttachShader(program, fs);
    gl.LinkProgram(program);
    GLint ok = 0;
    gl.GetProgramiv(program, GL_LINK_STATUS, &ok);
    if (ok) {
      printf("end\t%s\n", id);
    } else {
      char log[4096] = "";
      gl.GetProgramInfoLog(program, sizeof log, NULL, log);
      print_flat("fail", id, log, sizeof log);
    }
    gl.DeleteProgram(program);
  }
  if (vs) gl.DeleteShader(vs);
  if (fs) gl.DeleteShader(fs);
  fflush(stdout);
}

int main(int argc, char **argv) {
  if (argc != 2) die("usage: aovar-gl-stats LIST (one \"id<TAB>vertex<TAB>fragment\" a line)");
  FILE *list = fopen(argv[1], "r");
  if (!list) die("cannot read the list file");
  open_context();
  printf("renderer\t%s\nversion\t%s\n", gl.GetString(GL_RENDERER), gl.GetString(GL_VERSION));
  gl.Enable(GL_DEBUG_OUTPUT);
  gl.Enable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
  gl.DebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DONT_CARE, 0, NULL, GL_FALSE);
  gl.DebugMessageControl(GL_DEBUG_SOURCE_SHADER_COMPILER, GL_DEBUG_TYPE_OTHER, GL_DONT_CARE, 0, NULL, GL_TRUE);
  gl.DebugMessageCallback(on_message, NULL);
  char *line = NULL;
  size_t capacity = 0;
  while (getline(&line, &capacity, list) > 0) {
    line[strcspn(line, "\r\n")] = 0;
    char *vertex = strchr(line, '\t'), *fragment = vertex ? strchr(vertex + 1, '\t') : NULL;
    if (!fragment) continue;
    *vertex++ = 0;
    *fragment++ = 0;
    run_program(line, vertex, fragment);
  }
  free(line);
  fclose(list);
  return 0;
}
