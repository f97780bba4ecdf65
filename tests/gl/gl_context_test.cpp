// The headless EGL context: it is OpenGL >= 4.5 core, it renders (clears and a shader draw
// into framebuffer objects, read back exactly), GL errors are reported with their place, and
// several contexts can be created and destroyed in any order.
// The test target does not define GL_GLEXT_PROTOTYPES (the renderer library does): declare the
// core entry points, which libOpenGL exports.
#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
#include <GL/glcorearb.h>
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "oer/core/error.hpp"
#include "oer/gl/gl_context.hpp"

using namespace oer;

namespace {

// A framebuffer object with one color renderbuffer, bound for drawing and reading.
class Framebuffer {
  public:
    Framebuffer(GLenum format, int width, int height) : width_(width), height_(height) {
        glGenRenderbuffers(1, &color_);
        glBindRenderbuffer(GL_RENDERBUFFER, color_);
        glRenderbufferStorage(GL_RENDERBUFFER, format, width, height);
        glGenFramebuffers(1, &framebuffer_);
        glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color_);
        status_ = glCheckFramebufferStatus(GL_FRAMEBUFFER);
        glViewport(0, 0, width, height);
    }
    ~Framebuffer() {
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glDeleteFramebuffers(1, &framebuffer_);
        glDeleteRenderbuffers(1, &color_);
    }
    Framebuffer(const Framebuffer&) = delete;
    Framebuffer& operator=(const Framebuffer&) = delete;

    bool complete() const { return status_ == GL_FRAMEBUFFER_COMPLETE; }
    GLuint name() const { return framebuffer_; }

    std::vector<std::uint8_t> read_rgba8() const {
        std::vector<std::uint8_t> pixels(std::size_t(width_) * height_ * 4, 0);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
        return pixels;
    }
    std::vector<float> read_rgba32f() const {
        std::vector<float> pixels(std::size_t(width_) * height_ * 4, -7.0f);
        glReadPixels(0, 0, width_, height_, GL_RGBA, GL_FLOAT, pixels.data());
        return pixels;
    }

  private:
    int width_, height_;
    GLuint color_ = 0, framebuffer_ = 0;
    GLenum status_ = 0;
};

GLuint compile(GLenum stage, const char* source) {
    const GLuint shader = glCreateShader(stage);
    glShaderSource(shader, 1, &source, nullptr);
    glCompileShader(shader);
    GLint ok = GL_FALSE;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (ok != GL_TRUE) {
        char log[2048] = {};
        glGetShaderInfoLog(shader, sizeof log, nullptr, log);
        ADD_FAILURE() << "shader does not compile: " << log;
    }
    return shader;
}

// A program drawing one triangle that covers the viewport (from gl_VertexID: no vertex data)
// with the fragment shader given.
GLuint full_screen_program(const char* fragment_source) {
    static const char* vertex_source = R"(#version 450 core
void main() {
    vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
})";
    const GLuint vertex = compile(GL_VERTEX_SHADER, vertex_source);
    const GLuint fragment = compile(GL_FRAGMENT_SHADER, fragment_source);
    const GLuint program = glCreateProgram();
    glAttachShader(program, vertex);
    glAttachShader(program, fragment);
    glLinkProgram(program);
    glDeleteShader(vertex);
    glDeleteShader(fragment);
    GLint ok = GL_FALSE;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (ok != GL_TRUE) {
        char log[2048] = {};
        glGetProgramInfoLog(program, sizeof log, nullptr, log);
        ADD_FAILURE() << "program does not link: " << log;
    }
    return program;
}

void draw_full_screen(GLuint program) {
    GLuint vertex_array = 0;
    glGenVertexArrays(1, &vertex_array);  // core profile: a draw needs a vertex array object
    glBindVertexArray(vertex_array);
    glUseProgram(program);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glUseProgram(0);
    glBindVertexArray(0);
    glDeleteVertexArrays(1, &vertex_array);
}

std::string describe(const GlInfo& info) {
    std::string text = "platform " + info.platform + ", EGL " + info.egl_version + " (" +
                       info.egl_vendor + "), GL " + info.version + ", " + info.vendor + ", " +
                       info.renderer + ", max texture " + std::to_string(info.max_texture_size) +
                       ", max samples " + std::to_string(info.max_samples);
    for (const std::string& attempt : info.attempts) {
        text += "\n  before: " + attempt;
    }
    return text;
}

}  // namespace

TEST(GlContext, CreatesAnOpenGl45CoreContext) {
    const std::unique_ptr<GlContext> context = GlContext::create();
    const GlInfo& info = context->info();
    std::cout << "[ GL info  ] " << describe(info) << std::endl;

    EXPECT_TRUE(info.platform == "surfaceless" || info.platform == "device") << info.platform;
    EXPECT_FALSE(info.renderer.empty());
    EXPECT_FALSE(info.vendor.empty());
    EXPECT_FALSE(info.egl_version.empty());
    GLint major = 0, minor = 0, profile = 0, flags = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
    glGetIntegerv(GL_CONTEXT_FLAGS, &flags);
    EXPECT_TRUE(major > 4 || (major == 4 && minor >= 5)) << major << "." << minor;
    EXPECT_EQ(info.version.rfind(std::to_string(major) + "." + std::to_string(minor), 0), 0u)
        << info.version;
    EXPECT_NE(profile & GL_CONTEXT_CORE_PROFILE_BIT, 0);
    EXPECT_NE(glIsEnabled(GL_DEBUG_OUTPUT), GL_FALSE);
    std::cout << "[ GL info  ] debug context: " << ((flags & GL_CONTEXT_FLAG_DEBUG_BIT) != 0)
              << std::endl;
    // The minimums of OpenGL 4.5.
    EXPECT_GE(info.max_texture_size, 16384);
    EXPECT_GE(info.max_samples, 4);
    EXPECT_NO_THROW(check_gl_errors("after create"));
}

TEST(GlContext, ClearsFramebuffersToAKnownColor) {
    const std::unique_ptr<GlContext> context = GlContext::create();
    {
        Framebuffer target(GL_RGBA8, 17, 9);
        ASSERT_TRUE(target.complete());
        // Multiples of 1/255 convert exactly.
        glClearColor(51 / 255.0f, 102 / 255.0f, 153 / 255.0f, 204 / 255.0f);
        glClear(GL_COLOR_BUFFER_BIT);
        const std::vector<std::uint8_t> pixels = target.read_rgba8();
        for (std::size_t i = 0; i < pixels.size(); i += 4) {
            ASSERT_EQ(pixels[i], 51) << "pixel " << i / 4;
            ASSERT_EQ(pixels[i + 1], 102) << "pixel " << i / 4;
            ASSERT_EQ(pixels[i + 2], 153) << "pixel " << i / 4;
            ASSERT_EQ(pixels[i + 3], 204) << "pixel " << i / 4;
        }
    }
    {
        Framebuffer target(GL_RGBA32F, 8, 8);
        ASSERT_TRUE(target.complete());
        glClearColor(0.25f, -1.5f, 1000.0f, 0.125f);  // float targets are not clamped
        glClear(GL_COLOR_BUFFER_BIT);
        const std::vector<float> pixels = target.read_rgba32f();
        for (std::size_t i = 0; i < pixels.size(); i += 4) {
            ASSERT_EQ(pixels[i], 0.25f);
            ASSERT_EQ(pixels[i + 1], -1.5f);
            ASSERT_EQ(pixels[i + 2], 1000.0f);
            ASSERT_EQ(pixels[i + 3], 0.125f);
        }
    }
    EXPECT_NO_THROW(check_gl_errors("clears"));
}

TEST(GlContext, DrawsWithAShaderProgram) {
    const std::unique_ptr<GlContext> context = GlContext::create();
    const int width = 24, height = 16;
    Framebuffer target(GL_RGBA32F, width, height);
    ASSERT_TRUE(target.complete());

    // A constant color over a different clear color: every pixel is drawn.
    glClearColor(0.0f, 0.0f, 0.0f, 0.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    const GLuint constant = full_screen_program(R"(#version 450 core
layout(location = 0) out vec4 color;
void main() { color = vec4(1.0, 0.5, 0.25, 0.75); })");
    draw_full_screen(constant);
    std::vector<float> pixels = target.read_rgba32f();
    for (std::size_t i = 0; i < pixels.size(); i += 4) {
        ASSERT_EQ(pixels[i], 1.0f) << "pixel " << i / 4;
        ASSERT_EQ(pixels[i + 1], 0.5f) << "pixel " << i / 4;
        ASSERT_EQ(pixels[i + 2], 0.25f) << "pixel " << i / 4;
        ASSERT_EQ(pixels[i + 3], 0.75f) << "pixel " << i / 4;
    }
    glDeleteProgram(constant);

    // Each fragment writes its own window position: rasterisation hits every pixel centre,
    // once, where it should (row 0 at the bottom in GL).
    const GLuint position = full_screen_program(R"(#version 450 core
layout(location = 0) out vec4 color;
void main() { color = vec4(gl_FragCoord.xy, 7.0, 1.0); })");
    draw_full_screen(position);
    pixels = target.read_rgba32f();
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const float* p = &pixels[(std::size_t(y) * width + x) * 4];
            ASSERT_EQ(p[0], x + 0.5f) << x << "," << y;
            ASSERT_EQ(p[1], y + 0.5f) << x << "," << y;
            ASSERT_EQ(p[2], 7.0f) << x << "," << y;
        }
    }
    glDeleteProgram(position);
    EXPECT_NO_THROW(check_gl_errors("shader draws"));
}

TEST(GlContext, CheckGlErrorsReportsADeliberateErrorWithItsPlace) {
    const std::unique_ptr<GlContext> context = GlContext::create();
    EXPECT_NO_THROW(check_gl_errors("before"));
    glBindTexture(0x1234, 0);  // not a texture target: GL_INVALID_ENUM
    try {
        check_gl_errors("binding a texture to nowhere");
        FAIL() << "check_gl_errors did not throw";
    } catch (const Error& error) {
        const std::string message = error.what();
        std::cout << "[ message  ] " << message << std::endl;
        EXPECT_EQ(error.kind(), ErrorKind::Internal);
        EXPECT_NE(message.find("binding a texture to nowhere"), std::string::npos) << message;
        EXPECT_NE(message.find("GL_INVALID_ENUM"), std::string::npos) << message;
    }
    // Drained: the next check is clean, and a second error is reported again.
    EXPECT_NO_THROW(check_gl_errors("after"));
    glDrawArrays(GL_TRIANGLES, 0, -1);  // negative count: GL_INVALID_VALUE
    EXPECT_THROW(check_gl_errors("negative count"), Error);
    EXPECT_NO_THROW(check_gl_errors("after the second"));
}

TEST(GlContext, SeveralContextsAreIndependentAndDieInAnyOrder) {
    for (const bool first_dies_first : {true, false}) {
        std::unique_ptr<GlContext> a = GlContext::create();
        Framebuffer in_a(GL_RGBA8, 4, 4);
        const GLuint name_in_a = in_a.name();
        std::unique_ptr<GlContext> b = GlContext::create();  // now current
        // A fresh context does not see the first one's objects.
        EXPECT_EQ(glIsFramebuffer(name_in_a), GL_FALSE);
        a->make_current();
        EXPECT_EQ(glIsFramebuffer(name_in_a), GL_TRUE);
        EXPECT_NO_THROW(check_gl_errors("switching contexts"));
        if (first_dies_first) {
            b->make_current();
            a.reset();  // not current: destroyed at once, display kept for b
            {
                Framebuffer in_b(GL_RGBA8, 2, 2);
                glClearColor(1, 0, 0, 1);
                glClear(GL_COLOR_BUFFER_BIT);
                EXPECT_EQ(in_b.read_rgba8()[0], 255);
                EXPECT_NO_THROW(check_gl_errors("b after a died"));
            }
            b.reset();  // `in_a` died with a: its destructor's calls find no context
        } else {
            b.reset();  // not current
            Framebuffer again(GL_RGBA8, 2, 2);
            glClearColor(0, 1, 0, 1);
            glClear(GL_COLOR_BUFFER_BIT);
            EXPECT_EQ(again.read_rgba8()[1], 255);
            EXPECT_NO_THROW(check_gl_errors("a after b died"));
            // Framebuffer `in_a` belongs to a: a is current when it dies below.
        }
    }
    // Every display was released: a new context starts from scratch and works.
    const std::unique_ptr<GlContext> fresh = GlContext::create();
    EXPECT_FALSE(fresh->info().renderer.empty());
}

TEST(GlContext, ContextsOnSeveralThreadsAtOnce) {
    std::vector<std::thread> threads;
    std::array<int, 4> red = {};
    for (int t = 0; t < 4; ++t) {
        threads.emplace_back([t, &red] {
            for (int round = 0; round < 3; ++round) {
                const std::unique_ptr<GlContext> context = GlContext::create();
                Framebuffer target(GL_RGBA8, 8, 8);
                glClearColor(float(10 * (t + 1)) / 255.0f, 0, 0, 1);
                glClear(GL_COLOR_BUFFER_BIT);
                red[std::size_t(t)] = target.read_rgba8()[0];
            }
        });
    }
    for (std::thread& thread : threads) {
        thread.join();
    }
    for (int t = 0; t < 4; ++t) {
        EXPECT_EQ(red[std::size_t(t)], 10 * (t + 1));
    }
}

TEST(GlContext, MakeCurrentFailsWhileCurrentInAnotherThread) {
    const std::unique_ptr<GlContext> context = GlContext::create();
    std::string message;
    std::thread([&] {
        try {
            context->make_current();
        } catch (const Error& error) {
            message = error.what();
        }
    }).join();
    EXPECT_NE(message.find("EGL_BAD_ACCESS"), std::string::npos) << message;
    EXPECT_NO_THROW(context->make_current());  // still fine here
}

// With no EGL driver at all (glvnd pointed at a vendor file that does not exist), creation
// fails with Unsupported and says what each platform answered. In a child process, started
// afresh, since glvnd reads its vendors once.
TEST(GlContextDeathTest, NoDriverGivesUnsupportedListingEveryAttempt) {
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    EXPECT_EXIT(
        {
            setenv("__EGL_VENDOR_LIBRARY_FILENAMES", "/nonexistent/oer-no-vendor.json", 1);
            unsetenv("__EGL_VENDOR_LIBRARY_DIRS");
            try {
                GlContext::create();
            } catch (const Error& error) {
                std::cerr << error.what() << std::endl;
                std::exit(error.kind() == ErrorKind::Unsupported ? 0 : 2);
            }
            std::exit(1);
        },
        ::testing::ExitedWithCode(0), "no headless OpenGL 4.5.*device platform.*surfaceless");
}
