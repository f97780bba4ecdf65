#pragma once
// The GL renderer as the benchmarks drive it: one FrameRenderer on its own render thread (the
// thread of its EGL context), frames rendered synchronously. Header-only, so that
// oer_bench_support itself links no GL (preprocessing benchmarks link no EGL).
#include <memory>

#include "oer/gl/frame_renderer.hpp"
#include "oer/gl/render_thread.hpp"

namespace oer::bench {

class BenchRenderer {
  public:
    BenchRenderer() : thread_(std::make_unique<RenderThread>()) {
        renderer_ = thread_->submit([] { return std::make_shared<FrameRenderer>(); }).get();
    }
    ~BenchRenderer() {
        thread_->submit([this] { renderer_.reset(); }).get();
    }
    BenchRenderer(const BenchRenderer&) = delete;
    BenchRenderer& operator=(const BenchRenderer&) = delete;

    const GlInfo& info() const { return thread_->info(); }
    Frame render(const FrameRequest& request) {
        return thread_->submit([&] { return renderer_->render(request); }).get();
    }

  private:
    std::unique_ptr<RenderThread> thread_;
    std::shared_ptr<FrameRenderer> renderer_;
};

}  // namespace oer::bench
