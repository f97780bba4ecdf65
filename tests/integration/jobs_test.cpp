// Batch jobs over HTTP (POST /v1/jobs, docs/jobs.md): a turntable of 36 views x 2 variants
// followed to the end by its event stream, its frames by name, as spin sets and as a ZIP (a
// server killed mid-job and started again: tests/process/kill_restart_test.cpp);
// cancellation; the bounds per job and per client; malformed jobs named by member; the
// latency of interactive frames with and without a running job (printed); a client's listing
// of its jobs; and the retention of settled jobs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iterator>
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

namespace {

std::vector<std::string> listed_ids(const Json& page) {
    std::vector<std::string> ids;
    for (const Json& entry : page.value("jobs", Json::array())) {
        ids.push_back(entry.value("id", ""));
    }
    return ids;
}

}  // namespace

// GET /v1/jobs: the requesting client's jobs, newest first, a page at a time in the form of the
// other listings (limit, after, next); another client's jobs are never listed, nor usable as a
// cursor; a cursor that is not a job id, a limit out of 1..100 and an unknown parameter are 422.
TEST(JobsListing, AClientsOwnJobsNewestFirstAPageAtATime) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    std::vector<std::string> newest_first;
    for (int i = 0; i < 3; ++i) {
        newest_first.insert(newest_first.begin(), submit(*client, turntable(2)));
        ASSERT_FALSE(newest_first.front().empty());
    }
    const Json all = expect_conforms("GET", "/v1/jobs", client->Get("/v1/jobs"));
    EXPECT_EQ(listed_ids(all), newest_first);
    EXPECT_FALSE(all.contains("next"));
    for (const Json& entry : all.value("jobs", Json::array())) {
        EXPECT_EQ(entry.at("url"), "/v1/jobs/" + entry.at("id").get<std::string>());
        EXPECT_EQ(entry.at("total"), 2);
        // As GET /v1/jobs/{id} says it, at a moment of its own: never behind the listing.
        const Json status = job_status(*client, entry.at("id"));
        EXPECT_GE(status.at("done"), entry.at("done"));
    }

    const Json first = expect_conforms("GET", "/v1/jobs", client->Get("/v1/jobs?limit=2"));
    EXPECT_EQ(listed_ids(first), (std::vector<std::string>{newest_first[0], newest_first[1]}));
    ASSERT_EQ(first.value("next", ""), "/v1/jobs?limit=2&after=" + newest_first[1]);
    const Json second = expect_conforms("GET", "/v1/jobs",
                                        client->Get(first.at("next").get<std::string>().c_str()));
    EXPECT_EQ(listed_ids(second), std::vector<std::string>{newest_first[2]});
    EXPECT_FALSE(second.contains("next"));

    // Another client (another address) lists its own job alone, and the first client's list
    // stays its own.
    auto other = load_client(server.port(), 0, 60);
    const std::string theirs = submit(*other, turntable(1));
    ASSERT_FALSE(theirs.empty());
    EXPECT_EQ(listed_ids(expect_conforms("GET", "/v1/jobs", other->Get("/v1/jobs"))),
              std::vector<std::string>{theirs});
    EXPECT_EQ(listed_ids(expect_conforms("GET", "/v1/jobs", client->Get("/v1/jobs"))),
              newest_first);
    using server::ProblemKind;
    expect_problem("GET", "/v1/jobs", client->Get(("/v1/jobs?after=" + theirs).c_str()),
                   ProblemKind::InvalidParameter, "after");
    expect_problem("GET", "/v1/jobs",
                   client->Get(("/v1/jobs?after=" + std::string(64, 'a')).c_str()),
                   ProblemKind::InvalidParameter, "after");
    expect_problem("GET", "/v1/jobs", client->Get("/v1/jobs?limit=101"),
                   ProblemKind::InvalidParameter, "limit");
    expect_problem("GET", "/v1/jobs", client->Get("/v1/jobs?limit=0"),
                   ProblemKind::InvalidParameter, "limit");
    expect_problem("GET", "/v1/jobs", client->Get("/v1/jobs?page=2"), ProblemKind::InvalidParameter,
                   "page");
}

// With an API key, the listing needs it, as making and cancelling jobs do.
TEST(JobsListing, NeedsTheApiKeyWhenTheServerHasOne) {
    TempRoot root;
    server::ServiceConfig config = test_config(root.data());
    config.api_key = "s3cret-key";
    TestServer server(config);
    auto client = server.client();
    expect_problem("GET", "/v1/jobs", client->Get("/v1/jobs"), server::ProblemKind::Unauthorized);
    expect_problem("GET", "/v1/jobs",
                   client->Get("/v1/jobs", {{"Authorization", "Bearer wrong-key"}}),
                   server::ProblemKind::Unauthorized);
    const Json page = expect_conforms(
        "GET", "/v1/jobs", client->Get("/v1/jobs", {{"Authorization", "Bearer s3cret-key"}}));
    EXPECT_EQ(page, (Json{{"jobs", Json::array()}}));
}

namespace {

// Sets the write time of every file of the job's folder `age` back: its last change, as the
// retention reads it (JobStore::last_write), as if it had settled that long ago.
void age_job(const TempRoot& root, const std::string& id, std::chrono::hours age) {
    const auto when = std::filesystem::file_time_type::clock::now() - age;
    for (const auto& entry :
         std::filesystem::recursive_directory_iterator(root.data() / "jobs" / id)) {
        if (entry.is_regular_file()) {
            std::filesystem::last_write_time(entry.path(), when);
        }
    }
}

std::size_t stored_frame_files(const TempRoot& root, const std::string& id) {
    const auto frames = root.data() / "jobs" / id / "frames";
    return std::size_t(std::distance(std::filesystem::directory_iterator(frames),
                                     std::filesystem::directory_iterator()));
}

int status_code(httplib::Client& client, const std::string& path) {
    const auto answer = client.Get(path.c_str());
    return answer ? answer->status : 0;
}

}  // namespace

// A settled job (done, cancelled) unchanged for longer than --job-retention-hours is removed at
// start, its folder with it; a recent one is kept, and an unsettled one never, however old;
// with a retention of 0 nothing is removed.
TEST(JobsRetention, SettledJobsPastTheRetentionGoAtStartUnsettledOnesNever) {
    TempRoot root;
    std::string done_old, done_recent, cancelled_old, running_old;
    constexpr int kLongJob = 1000;  // seconds of frames: still running when its server stops
    {
        TestServer first(test_config(root.data()));
        auto client = first.client();
        done_old = submit(*client, turntable(1));
        done_recent = submit(*client, turntable(1));
        ASSERT_TRUE(eventually(
            [&] {
                return job_status(*client, done_old).at("state") == "done" &&
                       job_status(*client, done_recent).at("state") == "done";
            },
            std::chrono::minutes(1)));
        cancelled_old = submit(*client, turntable(kLongJob));
        client->Delete(("/v1/jobs/" + cancelled_old).c_str());
        running_old = submit(*client, turntable(kLongJob));
        ASSERT_TRUE(eventually([&] { return job_status(*client, running_old).at("done") >= 2; },
                               std::chrono::minutes(1)));
    }
    const auto age_old_jobs = [&] {
        ASSERT_LT(stored_frame_files(root, running_old), std::size_t(kLongJob));
        for (const std::string& id : {done_old, cancelled_old, running_old}) {
            age_job(root, id, std::chrono::hours(200));
        }
    };
    age_old_jobs();
    {
        server::ServiceConfig config = test_config(root.data());
        config.job_retention_hours = 0;
        TestServer keeping(config);
        auto client = keeping.client();
        for (const std::string& id : {done_old, done_recent, cancelled_old, running_old}) {
            EXPECT_EQ(status_code(*client, "/v1/jobs/" + id), 200) << id;
        }
    }
    age_old_jobs();  // the frames the resumed job stored meanwhile too

    server::ServiceConfig config = test_config(root.data());
    EXPECT_EQ(config.job_retention_hours, 168);
    TestServer server(config);
    auto client = server.client();
    for (const std::string& id : {done_old, cancelled_old}) {
        expect_problem("GET", "/v1/jobs/{id}", client->Get(("/v1/jobs/" + id).c_str()),
                       server::ProblemKind::UnknownId);
        EXPECT_FALSE(std::filesystem::exists(root.data() / "jobs" / id)) << id;
    }
    bool logged = false;
    for (const std::string& line : server.log_lines()) {
        logged |= line.find("jobs: job " + done_old + " (done) removed: unchanged for more than " +
                            "168 h (--job-retention-hours)") != std::string::npos;
    }
    EXPECT_TRUE(logged);
    for (const auto& entry : std::filesystem::directory_iterator(root.data() / "jobs")) {
        EXPECT_FALSE(entry.path().filename().string().starts_with("."))
            << entry.path() << " left behind";
    }
    ASSERT_EQ(status_code(*client, "/v1/jobs/" + running_old), 200) << "an unsettled job is gone";
    ASSERT_EQ(status_code(*client, "/v1/jobs/" + done_recent), 200) << "a recent job is gone";
    const Json running = job_status(*client, running_old);
    EXPECT_TRUE(running.at("state") == "queued" || running.at("state") == "running")
        << running.dump();
    EXPECT_EQ(job_status(*client, done_recent).at("state"), "done");
    std::vector<std::string> listed =
        listed_ids(expect_conforms("GET", "/v1/jobs", client->Get("/v1/jobs")));
    std::sort(listed.begin(), listed.end());
    std::vector<std::string> kept{done_recent, running_old};
    std::sort(kept.begin(), kept.end());
    EXPECT_EQ(listed, kept);
    client->Delete(("/v1/jobs/" + running_old).c_str());
}
