// Batch jobs over HTTP (POST /v1/jobs, docs/jobs.md): a turntable of 36 views x 2 variants
// followed to the end by its event stream, its frames by name, as spin sets and as a ZIP (a
// server killed mid-job and started again: tests/process/kill_restart_test.cpp);
// cancellation; the bounds per job and per client; malformed jobs named by member; and the
// latency of interactive frames with and without a running job (printed).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <thread>

#include <webp/demux.h>

#include "../mesh/gltf_test_assets.hpp"
#include "http_support.hpp"
#include "oer/mesh/camera.hpp"

using namespace oer;
using namespace oer::itest;

namespace {

std::string variants_glb() {
    const std::vector<std::uint8_t> bytes = mesh_testing::variants_product().glb();
    return std::string(bytes.begin(), bytes.end());
}

// A small, quick frame: the tests count and compare frames, they do not look at them.
Json small_render(const std::string& mesh = "default") {
    return {{"environment", "default"},
            {"objects", Json::array({{{"mesh", mesh}}})},
            {"width", 64},
            {"height", 48},
            {"samples", 1},
            {"format", "png"},
            {"shadows", {{"resolution", 256}}}};
}

Json turntable(int views, const Json& render = small_render()) {
    return {{"turntable", {{"render", render}, {"views", views}}}};
}

std::string submit(httplib::Client& client, const Json& job) {
    const auto answer = post_json(client, "/v1/jobs", job);
    const Json status = expect_conforms("POST", "/v1/jobs", answer);
    EXPECT_EQ(answer ? answer->status : 0, 202);
    EXPECT_TRUE(status.is_object());
    if (!status.is_object()) {
        return "";
    }
    EXPECT_EQ(answer->get_header_value("Location"), "/v1/jobs/" + status.value("id", ""));
    return status.value("id", "");
}

Json job_status(httplib::Client& client, const std::string& id) {
    return expect_conforms("GET", "/v1/jobs/{id}", client.Get(("/v1/jobs/" + id).c_str()));
}

double stored_frames(httplib::Client& client) {
    return scrape(client).sum("oer_job_frames_stored_total");
}

// The count once it has caught up with the files (a frame's file is written just before it is
// counted), and a little longer, so that a frame counted twice would show.
double stored_frames_at_least(httplib::Client& client, double expected) {
    eventually([&] { return stored_frames(client) >= expected; }, std::chrono::seconds(5));
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    return stored_frames(client);
}

// The views of an animated WebP, decoded by libwebpdemux's animation decoder.
std::vector<Rgba8Image> webp_views(const std::string& bytes) {
    WebPData data{reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()};
    WebPAnimDecoderOptions options;
    WebPAnimDecoderOptionsInit(&options);
    options.color_mode = MODE_RGBA;
    std::vector<Rgba8Image> views;
    WebPAnimDecoder* decoder = WebPAnimDecoderNew(&data, &options);
    if (!decoder) {
        ADD_FAILURE() << "not an animated WebP";
        return views;
    }
    WebPAnimInfo info;
    WebPAnimDecoderGetInfo(decoder, &info);
    while (WebPAnimDecoderHasMoreFrames(decoder)) {
        std::uint8_t* pixels = nullptr;
        int timestamp = 0;
        if (!WebPAnimDecoderGetNext(decoder, &pixels, &timestamp)) {
            ADD_FAILURE() << "a view does not decode";
            break;
        }
        views.push_back({int(info.canvas_width), int(info.canvas_height),
                         std::vector<std::uint8_t>(pixels, pixels + std::size_t(info.canvas_width) *
                                                                        info.canvas_height * 4)});
    }
    WebPAnimDecoderDelete(decoder);
    return views;
}

// The ZIP's entries by name, read from its central directory (the archive's own index).
std::map<std::string, std::uint32_t> zip_entries(const std::string& zip) {
    const auto u16 = [&](std::size_t at) {
        return std::uint32_t(std::uint8_t(zip[at])) | std::uint32_t(std::uint8_t(zip[at + 1])) << 8;
    };
    const auto u32 = [&](std::size_t at) { return u16(at) | u16(at + 2) << 16; };
    std::map<std::string, std::uint32_t> entries;  // name -> size
    if (zip.size() < 22 || u32(zip.size() - 22) != 0x06054b50) {
        ADD_FAILURE() << "no end of central directory record";
        return entries;
    }
    std::size_t at = u32(zip.size() - 22 + 16);
    for (std::uint32_t i = 0; i < u16(zip.size() - 22 + 10); ++i) {
        EXPECT_EQ(u32(at), 0x02014b50u);
        const std::uint32_t size = u32(at + 24);
        const std::uint32_t name_length = u16(at + 28);
        const std::uint32_t local = u32(at + 42);
        EXPECT_EQ(u32(local), 0x04034b50u);
        entries[zip.substr(at + 46, name_length)] = size;
        at += 46 + name_length + u16(at + 30) + u16(at + 32);
    }
    return entries;
}

}  // namespace

// Slow: 72 frames and their outputs took 182 s under the sanitizers (about 12 s optimised), so
// the optimised build runs it; the parsers and bounds it shares with the tests below are
// sanitized there.
TEST(Jobs, TurntableOf36ViewsAndTwoVariantsCompletesSlow) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    const Json mesh = upload_mesh(*client, variants_glb(), "model/gltf-binary");
    ASSERT_FALSE(HasFatalFailure());
    const std::string mesh_id = mesh.at("id");
    wait_for_preparation(*client, mesh_id);

    Json job = turntable(36, small_render(mesh_id));
    job["turntable"]["variants"] = {"Red", "Blue"};
    const auto start = std::chrono::steady_clock::now();
    const std::string id = submit(*client, job);
    ASSERT_FALSE(id.empty());

    // Followed by its event stream to the end: the stream closes after the settled job's event.
    const EventStream stream = follow_events(*server.client(), "/v1/jobs/" + id + "/events");
    const double seconds = seconds_since(start);
    ASSERT_TRUE(stream.ended);
    EXPECT_EQ(stream.content_type, "text/event-stream");
    ASSERT_FALSE(stream.events.empty());
    EXPECT_EQ(stream.events.back().at("state"), "done");
    for (std::size_t i = 1; i < stream.events.size(); ++i) {
        EXPECT_GE(stream.events[i].at("done"), stream.events[i - 1].at("done"));
    }

    const Json status = job_status(*client, id);
    EXPECT_EQ(status.at("state"), "done");
    EXPECT_EQ(status.at("total"), 72);
    EXPECT_EQ(status.at("done"), 72);
    EXPECT_EQ(status.at("sequences"), (Json{"Red", "Blue"}));
    EXPECT_EQ(stored_frames_at_least(*client, 72.0), 72.0);
    std::printf("[ jobs ] 72 frames of 64x48 (36 views x 2 variants): %.2f s, %.1f frames/s\n",
                seconds, 72.0 / seconds);

    // Each frame by name, drawn as the same request to POST /v1/render draws it.
    const auto frame = client->Get(("/v1/jobs/" + id + "/frames/Blue-009").c_str());
    expect_conforms("GET", "/v1/jobs/{id}/frames/{name}", frame);
    const Rgba8Image image = decode_image(frame);
    EXPECT_EQ(image.width, 64);
    EXPECT_EQ(image.height, 48);
    Json alone = small_render(mesh_id);
    alone["objects"][0]["variant"] = "Blue";
    alone["camera"] = {{"orbit", {{"yaw", std::fmod(Orbit{}.yaw + 90.0, 360.0)}}}};
    const auto rendered = post_json(*client, "/v1/render", alone);
    ASSERT_TRUE(rendered && frame);
    EXPECT_EQ(rendered->body, frame->body);
    expect_problem("GET", "/v1/jobs/{id}/frames/{name}",
                   client->Get(("/v1/jobs/" + id + "/frames/Green-000").c_str()),
                   server::ProblemKind::NotFound);

    // The sequence as an animated WebP (lossy: near its views) and as a sprite sheet (exactly
    // its views, in rows of 6).
    const auto webp = client->Get(("/v1/jobs/" + id + "/sequences/Blue?quality=100").c_str());
    expect_conforms("GET", "/v1/jobs/{id}/sequences/{name}", webp);
    ASSERT_TRUE(webp);
    const std::vector<Rgba8Image> views = webp_views(webp->body);
    ASSERT_EQ(views.size(), 36u);
    EXPECT_EQ(views[9].width, 64);
    EXPECT_LT(frame_difference(views[9], image).mean, 4.0);
    const auto sheet = client->Get(("/v1/jobs/" + id + "/sequences/Blue?format=png").c_str());
    expect_conforms("GET", "/v1/jobs/{id}/sequences/{name}", sheet);
    ASSERT_TRUE(sheet);
    EXPECT_EQ(sheet->get_header_value("X-Oer-Sprite-Columns"), "6");
    const Rgba8Image sprites = decode_image(sheet);
    ASSERT_EQ(sprites.width, 6 * 64);
    ASSERT_EQ(sprites.height, 6 * 48);
    for (int y = 0; y < 48; ++y) {  // view 9: row 1, column 3
        const auto row = sprites.pixels.begin() + ((48 + y) * sprites.width + 3 * 64) * 4;
        ASSERT_TRUE(std::equal(row, row + 64 * 4, image.pixels.begin() + y * 64 * 4)) << y;
    }
    expect_problem("GET", "/v1/jobs/{id}/sequences/{name}",
                   client->Get(("/v1/jobs/" + id + "/sequences/Green").c_str()),
                   server::ProblemKind::NotFound);

    const auto zip = client->Get(("/v1/jobs/" + id + "/zip").c_str());
    expect_conforms("GET", "/v1/jobs/{id}/zip", zip);
    ASSERT_TRUE(zip);
    const auto entries = zip_entries(zip->body);
    EXPECT_EQ(entries.size(), 72u);
    EXPECT_EQ(entries.count("Red-000.png"), 1u);
    EXPECT_EQ(entries.at("Blue-009.png"), frame->body.size());
    EXPECT_NE(zip->body.find(frame->body), std::string::npos);
}

TEST(Jobs, CancelledJobRendersNoMoreFrames) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    const std::string id = submit(*client, turntable(400));
    ASSERT_FALSE(id.empty());
    ASSERT_TRUE(eventually([&] { return job_status(*client, id).at("done") >= 2; },
                           std::chrono::minutes(1)));
    const auto cancelled = client->Delete(("/v1/jobs/" + id).c_str());
    const Json answer = expect_conforms("DELETE", "/v1/jobs/{id}", cancelled);
    EXPECT_EQ(answer.at("state"), "cancelled");
    // At most the frame in flight is stored after the cancellation, then nothing.
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    const double after = stored_frames(*client);
    std::this_thread::sleep_for(std::chrono::milliseconds(700));
    EXPECT_EQ(stored_frames(*client), after);
    const Json status = job_status(*client, id);
    EXPECT_EQ(status.at("state"), "cancelled");
    EXPECT_LT(status.at("done").get<int>(), 400);
    expect_problem("DELETE", "/v1/jobs/{id}",
                   client->Delete("/v1/jobs/0123456789abcdef0123456789abcdef"),
                   server::ProblemKind::UnknownId);
}

TEST(Jobs, AreBoundedPerJobAndPerClient) {
    TempRoot root;
    server::ServiceConfig config = test_config(root.data());
    config.job_max_frames = 50;
    config.job_max_pixels = 50 * 256 * 256;
    config.client_job_frames = 60;
    TestServer server(config);
    auto client = server.client();
    expect_problem("POST", "/v1/jobs", post_json(*client, "/v1/jobs", turntable(51)),
                   server::ProblemKind::LimitExceeded, "turntable/views");
    Json large = small_render();
    large["width"] = 1024;
    large["height"] = 1024;
    expect_problem("POST", "/v1/jobs", post_json(*client, "/v1/jobs", turntable(4, large)),
                   server::ProblemKind::LimitExceeded, "body");
    // 40 frames of 256x256 with 8 samples take seconds: the first job is far from finished when
    // the second comes, and the two together pass the client's 60 frames.
    Json slow = small_render();
    slow["width"] = 256;
    slow["height"] = 256;
    slow["samples"] = 8;
    const std::string first = submit(*client, turntable(40, slow));
    ASSERT_FALSE(first.empty());
    const auto refused = post_json(*client, "/v1/jobs", turntable(40, slow));
    expect_problem("POST", "/v1/jobs", refused, server::ProblemKind::TooManyRenders);
    ASSERT_TRUE(refused);
    EXPECT_FALSE(refused->get_header_value("Retry-After").empty());
    EXPECT_LT(job_status(*client, first).at("done"), 20);
    client->Delete(("/v1/jobs/" + first).c_str());
    // Once it is cancelled, its frames no longer count.
    const std::string second = submit(*client, turntable(40, slow));
    EXPECT_EQ(second.size(), 32u);
    client->Delete(("/v1/jobs/" + second).c_str());
}

TEST(Jobs, MalformedJobsNameTheMember) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    const auto refused = [&](const Json& job, server::ProblemKind kind,
                             const std::string& parameter) {
        SCOPED_TRACE(job.dump());
        expect_problem("POST", "/v1/jobs", post_json(*client, "/v1/jobs", job), kind, parameter);
    };
    using server::ProblemKind;
    refused(turntable(0), ProblemKind::InvalidParameter, "turntable/views");
    refused(Json{{"frames", Json::array()}}, ProblemKind::InvalidParameter, "frames");
    refused(Json::object(), ProblemKind::InvalidParameter, "body");
    refused(Json{{"frames", {{{"name", "a"}, {"render", small_render()}}}}, {"turntable", 1}},
            ProblemKind::InvalidParameter, "body");
    refused(Json{{"frame", 1}}, ProblemKind::InvalidParameter, "frame");
    Json wide = small_render();
    wide["width"] = 0;
    refused(Json{{"frames", {{{"name", "a"}, {"render", wide}}}}}, ProblemKind::InvalidParameter,
            "frames/0/render/width");
    refused(Json{{"frames", {{{"name", "a/b"}, {"render", small_render()}}}}},
            ProblemKind::InvalidParameter, "frames/0/name");
    refused(Json{{"frames",
                  {{{"name", "a"}, {"render", small_render()}},
                   {{"name", "a"}, {"render", small_render()}}}}},
            ProblemKind::InvalidParameter, "frames/1/name");
    Json unknown = small_render();
    unknown["environment"] = std::string(64, 'a');
    refused(Json{{"frames", {{{"name", "a"}, {"render", unknown}}}}}, ProblemKind::UnknownId,
            "frames/0/render/environment");
    Json variant = small_render();
    variant["objects"][0]["variant"] = "Green";
    refused(Json{{"frames", {{{"name", "a"}, {"render", variant}}}}}, ProblemKind::InvalidParameter,
            "frames/0/render/objects/0/variant");
    Json look_at = small_render();
    look_at["camera"] = {{"eye", {0, 1, 3}}, {"target", {0, 0, 0}}};
    refused(Json{{"turntable", {{"render", look_at}, {"views", 4}}}}, ProblemKind::InvalidParameter,
            "turntable/render/camera");
    Json sizes = turntable(4);
    sizes["turntable"]["sizes"] = {{{"width", 64}}};
    refused(sizes, ProblemKind::InvalidParameter, "turntable/sizes/0/height");
    expect_problem("POST", "/v1/jobs",
                   client->Post("/v1/jobs", "{\"frames\": [", "application/json"),
                   ProblemKind::MalformedRequest);
    expect_problem("GET", "/v1/jobs/{id}", client->Get("/v1/jobs/0123456789abcdef0123456789abcdef"),
                   ProblemKind::UnknownId);
}

// Interactive frames (a shopper turning the product: uncached, a new yaw each) timed alone and
// while a job of larger frames runs, in alternating phases of one run (4 of each, 3 frames a
// phase), so that the machine's other load weighs on both alike; printed, not asserted (speed
// is measured in this project). What is asserted: each job was running through its phase, so
// the frames did share the machine with it.
TEST(Jobs, InteractiveLatencyWithAndWithoutAJobSlow) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    int yaw = 0;
    const auto interactive_ms = [&](int count, std::vector<double>& ms) {
        for (int i = 0; i < count; ++i) {
            const auto start = std::chrono::steady_clock::now();
            const auto frame = client->Get(("/v1/render?environment=default&mesh=default&width=256"
                                            "&height=256&samples=4&yaw=" +
                                            std::to_string(++yaw))
                                               .c_str());
            EXPECT_EQ(frame ? frame->status : 0, 200);
            ms.push_back(1000.0 * seconds_since(start));
        }
    };
    std::vector<double> warm, alone, beside_job;
    interactive_ms(2, warm);  // the default scene's caches
    Json render = small_render();
    render["width"] = 256;
    render["height"] = 256;
    render["samples"] = 4;
    double job_seconds = 0.0;
    double job_frames = 0.0;
    for (int phase = 0; phase < 4; ++phase) {
        interactive_ms(3, alone);
        const auto job_start = std::chrono::steady_clock::now();
        const std::string id = submit(*client, turntable(200, render));
        ASSERT_FALSE(id.empty());
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
        interactive_ms(3, beside_job);
        const Json status = job_status(*client, id);
        EXPECT_TRUE(status.at("state") == "queued" || status.at("state") == "running")
            << status.dump();
        job_frames += status.at("done").get<double>();
        job_seconds += seconds_since(job_start);
        client->Delete(("/v1/jobs/" + id).c_str());
    }
    const double yielded = scrape(*client).sum("oer_batch_frames_yielded_total");
    const double alone_ms = percentile(alone, 0.5);
    const double beside_ms = percentile(beside_job, 0.5);
    std::printf(
        "[ jobs ] interactive 256x256 frame, median of 12 in 4 alternating phases: %.1f ms "
        "alone, %.1f ms beside a running job (x%.2f); the jobs made %.2f frames/s of 256x256 "
        "over their phases (each 200 ms alone first), %.0f of them stopped to let an "
        "interactive frame go first\n",
        alone_ms, beside_ms, beside_ms / alone_ms, job_frames / job_seconds, yielded);
}
