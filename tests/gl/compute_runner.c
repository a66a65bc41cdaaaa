/* Runs a GLSL compute shader on a headless OpenGL 4.3 context (EGL with
 * EGL_PLATFORM_SURFACELESS_MESA: Mesa's llvmpipe needs no GPU and no
 * display) over a batch of points, for tests/test_codegen_headers.c, which
 * compiles this file at test time with `cc ... -lEGL -lGL`.
 *
 * usage: compute_runner SHADER.comp IN.bin OUT.bin
 *   IN.bin:  int32 n, then n int32 function indices, then 2n vec4 inputs
 *            (two per point: up to 8 arguments);
 *   OUT.bin: n vec4 outputs.
 * The shader reads the indices from binding 0, the inputs from binding 1
 * (point i: inputs[2 i], inputs[2 i + 1]),
 * writes binding 2, has local_size_x = 64 and a uniform uint `count`.
 * Prints the renderer's name; exit 1 with a message on any failure. */
#include <EGL/egl.h>
#include <EGL/eglext.h>
#define GL_GLEXT_PROTOTYPES
#include <GL/gl.h>
#include <GL/glext.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int fail(const char *what) {
  fprintf(stderr, "compute_runner: %s\n", what);
  return 1;
}

static char *read_all(const char *path, long *size) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  fseek(f, 0, SEEK_END);
  *size = ftell(f);
  fseek(f, 0, SEEK_SET);
  char *data = malloc((size_t)*size + 1);
  if (data && fread(data, 1, (size_t)*size, f) != (size_t)*size) {
    free(data);
    data = NULL;
  }
  if (data) data[*size] = '\0';
  fclose(f);
  return data;
}

static int make_context(void) {
  PFNEGLGETPLATFORMDISPLAYEXTPROC get_display =
      (PFNEGLGETPLATFORMDISPLAYEXTPROC)eglGetProcAddress("eglGetPlatformDisplayEXT");
  if (!get_display) return fail("eglGetPlatformDisplayEXT missing (install libegl-mesa0)");
  EGLDisplay display = get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
  EGLint major, minor;
  if (display == EGL_NO_DISPLAY || !eglInitialize(display, &major, &minor))
    return fail("eglInitialize failed (install libegl-mesa0 libgl1-mesa-dri)");
  if (!eglBindAPI(EGL_OPENGL_API)) return fail("eglBindAPI(EGL_OPENGL_API) failed");
  const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 3,
                               EGL_CONTEXT_OPENGL_PROFILE_MASK,
                               EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  EGLContext context = eglCreateContext(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
  if (context == EGL_NO_CONTEXT) return fail("no OpenGL 4.3 core context");
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context))
    return fail("eglMakeCurrent failed");
  printf("renderer: %s | %s\n", (const char *)glGetString(GL_RENDERER),
         (const char *)glGetString(GL_VERSION));
  return 0;
}

static GLuint make_program(const char *source) {
  GLuint shader = glCreateShader(GL_COMPUTE_SHADER);
  glShaderSource(shader, 1, &source, NULL);
  glCompileShader(shader);
  GLint ok = 0;
  char log[8192];
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    glGetShaderInfoLog(shader, sizeof log, NULL, log);
    fprintf(stderr, "compute_runner: compile failed:\n%s\n", log);
    return 0;
  }
  GLuint program = glCreateProgram();
  glAttachShader(program, shader);
  glLinkProgram(program);
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    glGetProgramInfoLog(program, sizeof log, NULL, log);
    fprintf(stderr, "compute_runner: link failed:\n%s\n", log);
    return 0;
  }
  return program;
}

static GLuint buffer(GLuint binding, GLsizeiptr size, const void *data) {
  GLuint b;
  glGenBuffers(1, &b);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, b);
  glBufferData(GL_SHADER_STORAGE_BUFFER, size, data, data ? GL_STATIC_DRAW : GL_DYNAMIC_READ);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, b);
  return b;
}

int main(int argc, char **argv) {
  if (argc != 4) return fail("usage: compute_runner SHADER.comp IN.bin OUT.bin");
  long source_size, input_size;
  char *source = read_all(argv[1], &source_size);
  char *input = read_all(argv[2], &input_size);
  if (!source || !input || input_size < 4) return fail("cannot read the shader or the input");
  int n;
  memcpy(&n, input, 4);
  if (n <= 0 || input_size != 4 + (long)n * 36) return fail("input size does not match n");
  if (make_context() != 0) return 1;
  GLuint program = make_program(source);
  if (!program) return 1;
  glUseProgram(program);
  glUniform1ui(glGetUniformLocation(program, "count"), (GLuint)n);
  buffer(0, (GLsizeiptr)n * 4, input + 4);
  buffer(1, (GLsizeiptr)n * 32, input + 4 + (long)n * 4);
  buffer(2, (GLsizeiptr)n * 16, NULL);
  glDispatchCompute((GLuint)((n + 63) / 64), 1, 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
  const float *out = glMapBufferRange(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)n * 16, GL_MAP_READ_BIT);
  if (!out || glGetError() != GL_NO_ERROR) return fail("reading the results back failed");
  FILE *f = fopen(argv[3], "wb");
  if (!f || fwrite(out, 16, (size_t)n, f) != (size_t)n || fclose(f) != 0)
    return fail("cannot write the output");
  printf("evaluated %d points\n", n);
  return 0;
}
