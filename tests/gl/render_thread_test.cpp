// The render thread: one thread per context, jobs in order, exceptions through futures, a
// destructor that loses nothing, and several render threads side by side.
// The test target does not define GL_GLEXT_PROTOTYPES (the renderer library does): declare the
// core entry points, which libOpenGL exports.
#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
#include <GL/glcorearb.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <future>
#include <iostream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <sys/resource.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "oer/core/error.hpp"
#include "oer/gl/render_thread.hpp"

using namespace oer;

namespace {

// Clears an 8x8 RGBA8 framebuffer object of the current context to (r, g, b, 255) / 255 and
// reads back its centre pixel, packed as 0xRRGGBBAA.
std::uint32_t clear_and_read(int r, int g, int b) {
    GLuint color = 0, framebuffer = 0;
    glGenRenderbuffers(1, &color);
    glBindRenderbuffer(GL_RENDERBUFFER, color);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, 8, 8);
    glGenFramebuffers(1, &framebuffer);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color);
    glViewport(0, 0, 8, 8);
    glClearColor(float(r) / 255.0f, float(g) / 255.0f, float(b) / 255.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    std::array<std::uint8_t, 4> pixel = {};
    glReadPixels(4, 4, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, pixel.data());
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteFramebuffers(1, &framebuffer);
    glDeleteRenderbuffers(1, &color);
    check_gl_errors("clear_and_read");
    return std::uint32_t(pixel[0]) << 24 | std::uint32_t(pixel[1]) << 16 |
           std::uint32_t(pixel[2]) << 8 | pixel[3];
}

// The ids of this process's threads.
std::set<pid_t> thread_ids() {
    std::set<pid_t> ids;
    for (const auto& entry : std::filesystem::directory_iterator("/proc/self/task")) {
        ids.insert(pid_t(std::stol(entry.path().filename().string())));
    }
    return ids;
}

// A thread's nice value and name, from /proc/self/task/ID/stat (proc(5): the name in
// parentheses is field 2, nice field 19).
std::pair<int, std::string> nice_and_name(pid_t id) {
    std::ifstream in("/proc/self/task/" + std::to_string(id) + "/stat");
    const std::string stat((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::size_t open = stat.find('('), close = stat.rfind(')');
    std::istringstream fields(stat.substr(close + 2));  // from field 3 on
    std::string field;
    for (int i = 3; i <= 19; ++i) {
        fields >> field;
    }
    return {std::stoi(field), stat.substr(open + 1, close - open - 1)};
}

std::uint32_t packed(int r, int g, int b) {
    return std::uint32_t(r) << 24 | std::uint32_t(g) << 16 | std::uint32_t(b) << 8 | 255u;
}

// Makes a render thread with a nice increment of 5 and draws with it; 0 when its jobs and every
// thread started with it run at least 5 below this one (or at 19, the lowest), llvmpipe's
// rasterizers among them, else 1. Each thread is named on stderr with its nice value.
int nice_render_thread_check() {
    const int base = ::getpriority(PRIO_PROCESS, id_t(::gettid()));
    const int lowered_nice = std::min(base + 5, 19);  // the kernel's lowest
    const std::set<pid_t> before = thread_ids();
    RenderThread render(5);
    const int job_nice =
        render.submit([] { return ::getpriority(PRIO_PROCESS, id_t(::gettid())); }).get();
    const std::uint32_t pixel = render.submit([] { return clear_and_read(10, 20, 30); }).get();
    std::cerr << "jobs at nice " << job_nice << ", the test at " << base << "\n";
    bool lowered = job_nice == lowered_nice && pixel == packed(10, 20, 30);
    int rasterizers = 0;
    for (const pid_t id : thread_ids()) {
        if (before.count(id) == 0) {
            const auto [nice, name] = nice_and_name(id);
            std::cerr << name << " at nice " << nice << "\n";
            lowered = lowered && nice >= lowered_nice;
            rasterizers += name.rfind("llvmpipe-", 0) == 0 && nice == lowered_nice;
        }
    }
    return lowered && rasterizers >= 1 ? 0 : 1;
}

}  // namespace

TEST(RenderThread, JobsRunOnOneThreadThatIsNotTheCallers) {
    RenderThread render;
    std::vector<std::future<std::thread::id>> ids;
    for (int i = 0; i < 20; ++i) {
        ids.push_back(render.submit([] { return std::this_thread::get_id(); }));
    }
    const std::thread::id first = ids.front().get();
    EXPECT_NE(first, std::this_thread::get_id());
    for (std::size_t i = 1; i < ids.size(); ++i) {
        EXPECT_EQ(ids[i].get(), first) << "job " << i;
    }
}

TEST(RenderThread, JobsRunInSubmissionOrder) {
    RenderThread render;
    std::vector<int> order;  // touched by the render thread only, until the last future
    std::vector<std::future<void>> done;
    for (int i = 0; i < 100; ++i) {
        done.push_back(render.submit([&order, i] { order.push_back(i); }));
    }
    for (std::future<void>& future : done) {
        future.get();
    }
    ASSERT_EQ(order.size(), 100u);
    for (int i = 0; i < 100; ++i) {
        EXPECT_EQ(order[std::size_t(i)], i);
    }
}

TEST(RenderThread, AJobsExceptionReachesItsFutureAndTheThreadGoesOn) {
    RenderThread render;
    auto failing =
        render.submit([]() -> int { throw Error(ErrorKind::InvalidInput, "no such mesh"); });
    auto next = render.submit([] { return 42; });
    try {
        failing.get();
        FAIL() << "no exception";
    } catch (const Error& error) {
        EXPECT_EQ(error.kind(), ErrorKind::InvalidInput);
        EXPECT_STREQ(error.what(), "no such mesh");
    }
    EXPECT_EQ(next.get(), 42);
    // A GL error inside a job, turned into an exception, also travels.
    auto gl_failure = render.submit([] {
        glBindTexture(0x1234, 0);
        check_gl_errors("bad bind in a job");
    });
    EXPECT_THROW(gl_failure.get(), Error);
    EXPECT_EQ(render.submit([] { return clear_and_read(1, 2, 3); }).get(), packed(1, 2, 3));
}

TEST(RenderThread, TheContextIsCurrentInsideJobs) {
    RenderThread render;
    EXPECT_FALSE(render.info().renderer.empty());
    const std::string renderer =
        render
            .submit([] {
                const auto* text = glGetString(GL_RENDERER);
                return std::string(text != nullptr ? reinterpret_cast<const char*>(text) : "");
            })
            .get();
    EXPECT_EQ(renderer, render.info().renderer);
    EXPECT_EQ(render.submit([] { return clear_and_read(200, 100, 50); }).get(),
              packed(200, 100, 50));
}

TEST(RenderThread, TwoRenderThreadsServeFourCallersConcurrently) {
    RenderThread first, second;
    std::array<RenderThread*, 2> renders = {&first, &second};
    std::atomic<int> mismatches = 0;
    std::atomic<int> jobs = 0;
    std::vector<std::thread> callers;
    for (int caller = 0; caller < 4; ++caller) {
        callers.emplace_back([&, caller] {
            for (int round = 0; round < 25; ++round) {
                // Each render thread clears to its own color: red for one, blue for the other.
                std::array<std::future<std::uint32_t>, 2> results;
                std::array<std::uint32_t, 2> expected = {};
                for (int r = 0; r < 2; ++r) {
                    const int level = 10 * caller + round + 1;
                    const int red = r == 0 ? level : 0, blue = r == 1 ? level : 0;
                    expected[std::size_t(r)] = packed(red, caller, blue);
                    results[std::size_t(r)] = renders[std::size_t(r)]->submit(
                        [red, caller, blue] { return clear_and_read(red, caller, blue); });
                }
                for (int r = 0; r < 2; ++r) {
                    if (results[std::size_t(r)].get() != expected[std::size_t(r)]) {
                        ++mismatches;
                    }
                    ++jobs;
                }
            }
        });
    }
    for (std::thread& caller : callers) {
        caller.join();
    }
    EXPECT_EQ(jobs.load(), 4 * 25 * 2);
    EXPECT_EQ(mismatches.load(), 0);
    const auto first_id = first.submit([] { return std::this_thread::get_id(); }).get();
    const auto second_id = second.submit([] { return std::this_thread::get_id(); }).get();
    EXPECT_NE(first_id, second_id);
}

TEST(RenderThread, QueueDepthCountsWaitingJobsAndTheDestructorDrainsThem) {
    std::atomic<int> ran = 0;
    std::promise<void> release;
    std::shared_future<void> released = release.get_future().share();
    std::promise<void> blocking_started;
    std::vector<std::future<void>> futures;
    {
        RenderThread render;
        EXPECT_EQ(render.queue_depth(), 0u);
        futures.push_back(render.submit([&, released] {
            blocking_started.set_value();
            released.wait();
        }));
        blocking_started.get_future().wait();  // the first job runs: no longer waiting
        for (int i = 0; i < 50; ++i) {
            futures.push_back(render.submit([&ran] {
                std::this_thread::sleep_for(std::chrono::microseconds(200));
                ++ran;
            }));
        }
        EXPECT_EQ(render.queue_depth(), 50u);
        // A job that submits another one while the destructor is already draining.
        futures.push_back(
            render.submit([&render, &ran] { render.submit([&ran] { ran += 1000; }); }));
        EXPECT_EQ(render.queue_depth(), 51u);
        release.set_value();
    }  // the destructor runs here, with most jobs still queued
    EXPECT_EQ(ran.load(), 1050);
    for (std::future<void>& future : futures) {
        EXPECT_EQ(future.wait_for(std::chrono::seconds(0)), std::future_status::ready);
    }
}

TEST(RenderThread, ManyRenderThreadsComeAndGoInAnyOrder) {
    auto a = std::make_unique<RenderThread>();
    auto b = std::make_unique<RenderThread>();
    auto c = std::make_unique<RenderThread>();
    b.reset();  // the middle one first
    EXPECT_EQ(a->submit([] { return clear_and_read(9, 9, 9); }).get(), packed(9, 9, 9));
    a.reset();
    EXPECT_EQ(c->submit([] { return clear_and_read(7, 8, 9); }).get(), packed(7, 8, 9));
    auto d = std::make_unique<RenderThread>();
    c.reset();
    EXPECT_EQ(d->submit([] { return clear_and_read(1, 1, 1); }).get(), packed(1, 1, 1));
}

// A context that cannot be created: the constructor rethrows GlContext::create's error (in a
// child process with no EGL vendor, see gl_context_test.cpp).
TEST(RenderThreadDeathTest, ConstructorRethrowsACreationFailure) {
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    EXPECT_EXIT(
        {
            setenv("__EGL_VENDOR_LIBRARY_FILENAMES", "/nonexistent/oer-no-vendor.json", 1);
            unsetenv("__EGL_VENDOR_LIBRARY_DIRS");
            try {
                RenderThread render;
            } catch (const Error& error) {
                std::cerr << error.what() << std::endl;
                std::exit(error.kind() == ErrorKind::Unsupported ? 0 : 2);
            }
            std::exit(1);
        },
        ::testing::ExitedWithCode(0), "no headless OpenGL");
}

// A render thread made with a nice increment runs its jobs below its creator, and so do the
// threads the driver starts for its context (llvmpipe's rasterizers, named llvmpipe-N, and
// helpers that keep the render thread's name), which inherit it; Mesa's shader-cache thread
// lowers itself further, to 19. In a process of its own (the death test's threadsafe style runs
// the test again in a new one), since the driver starts its threads with the process's first
// context and shares them after.
TEST(RenderThreadDeathTest, ANiceIncrementLowersItAndTheThreadsTheDriverStarts) {
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    EXPECT_EXIT(std::_Exit(nice_render_thread_check()), ::testing::ExitedWithCode(0), "");
}

TEST(RenderThread, ANiceIncrementOutsideZeroToNineteenIsRefused) {
    try {
        RenderThread render(20);
        ADD_FAILURE() << "a nice increment of 20 was taken";
    } catch (const Error& error) {
        EXPECT_EQ(error.kind(), ErrorKind::InvalidInput);
        EXPECT_NE(std::string(error.what()).find("0..19"), std::string::npos) << error.what();
    }
    EXPECT_THROW(RenderThread(-1), Error);
}
