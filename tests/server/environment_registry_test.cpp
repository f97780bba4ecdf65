// Uploaded environments listed and removed: a removal takes the rig, its record, its specular
// cube and (when no other rig uses it) its map, from the store and from memory; each state a
// crash can leave part way is the whole environment or none; and removals racing uploads of
// the same environment leave memory and the store in agreement.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <mutex>
#include <thread>

#include "environment_registry.hpp"
#include "oer/api/content_id.hpp"
#include "oer/image/image_encoding.hpp"
#include "oer/server/metrics.hpp"
#include "synthetic_maps.hpp"

using namespace oer;
using namespace oer::server;
namespace fs = std::filesystem;

namespace {

// A dim sky with one bright disc, as OpenEXR bytes.
std::string map_bytes(float brightness) {
    const HdrImage map = oer::testing::disc_map(64, 32, {0.05f, 0.05f, 0.06f},
                                                {{{0.3, 0.8, 0.2}, 0.2, {brightness, 38.0f, 35.0f}},
                                                 {{-0.6, 0.4, -0.5}, 0.15, {12.0f, 12.0f, 14.0f}}});
    std::vector<float> rgba(map.pixel_count() * 4, 1.0f);
    for (std::size_t i = 0; i < map.pixel_count(); ++i) {
        std::copy_n(&map.pixels[i * 3], 3, &rgba[i * 4]);
    }
    const std::vector<std::uint8_t> exr = encode_exr(map.width, map.height, rgba);
    return std::string(exr.begin(), exr.end());
}

RigOptions lights(int count) {
    RigOptions options;
    options.light_count = count;
    return options;
}

class EnvironmentRegistryTest : public ::testing::Test {
  protected:
    EnvironmentRegistryTest()
        : folder_(fs::temp_directory_path() /
                  ("oer-environment-registry-test-" + std::to_string(::getpid()) + "-" +
                   ::testing::UnitTest::GetInstance()->current_test_info()->name())),
          store_(folder_, [this](std::string_view line) { log(line); }),
          metrics_(registry_) {
        restart();
    }
    ~EnvironmentRegistryTest() override {
        environments_.reset();
        fs::remove_all(folder_);
    }

    // A new registry over the same store, as after a restart of the server.
    void restart() {
        environments_.reset();
        environments_ = std::make_unique<EnvironmentRegistry>(
            store_, metrics_, budget_, [this](std::string_view line) { log(line); }, ImageLimits{},
            64 << 20);
    }

    void log(std::string_view line) {
        const std::lock_guard lock(log_mutex_);
        log_.emplace_back(line);
    }

    // Every file under the data folder (temporary files included).
    std::vector<std::string> stored_files() const {
        std::vector<std::string> files;
        for (const auto& entry : fs::recursive_directory_iterator(folder_)) {
            if (entry.is_regular_file()) {
                files.push_back(fs::relative(entry.path(), folder_).string());
            }
        }
        std::sort(files.begin(), files.end());
        return files;
    }

    std::vector<std::string> listed_ids() {
        std::vector<std::string> ids;
        for (const ListedAsset& entry : environments_->list("", 1000).entries) {
            ids.push_back(entry.id);
        }
        return ids;
    }

    const fs::path folder_;
    AssetStore store_;
    MetricsRegistry registry_;
    ServiceMetrics metrics_;
    UploadBudget budget_{UploadBudgetLimits{}};
    std::unique_ptr<EnvironmentRegistry> environments_;
    std::mutex log_mutex_;
    std::vector<std::string> log_;
};

}  // namespace

TEST_F(EnvironmentRegistryTest, RemoveTakesTheRigItsRecordItsCubeAndItsMap) {
    const std::string bytes = map_bytes(40.0f);
    const auto uploaded = environments_->upload(bytes, "exr", lights(2), "map.exr").asset;
    const std::string id = uploaded->id;
    const std::string map_id = api::sha256_hex(bytes);
    ASSERT_NE(environments_->specular(*uploaded), nullptr);
    EXPECT_EQ(stored_files(),
              (std::vector<std::string>{"environments/" + map_id + ".exr",
                                        "rig-sources/" + id + ".sealed", "rigs/" + id + ".sealed",
                                        "specular/" + id + ".sealed"}));

    EXPECT_TRUE(environments_->remove(id));
    EXPECT_TRUE(stored_files().empty());
    EXPECT_EQ(environments_->find(id), nullptr) << "still in memory";
    EXPECT_TRUE(listed_ids().empty());
    EXPECT_EQ(environments_->source_image(*uploaded), nullptr) << "the decoded map is remembered";
    EXPECT_FALSE(environments_->remove(id)) << "removed twice";
    // A frame that held the environment keeps it whole.
    EXPECT_EQ(uploaded->json.at("id"), id);
    EXPECT_EQ(uploaded->json.at("lights").size(), uploaded->rig->lights.size());
    restart();
    EXPECT_EQ(environments_->find(id), nullptr);

    // The same bytes and options make the same environment again.
    const auto again = environments_->upload(bytes, "exr", lights(2), "map.exr");
    EXPECT_FALSE(again.cached);
    EXPECT_EQ(again.asset->id, id);
    EXPECT_NE(environments_->find(id), nullptr);
}

TEST_F(EnvironmentRegistryTest, AMapStaysWhileAnotherRigWasMadeFromIt) {
    const std::string bytes = map_bytes(40.0f);
    const std::string one = environments_->upload(bytes, "exr", lights(1), "map.exr").asset->id;
    const std::string two = environments_->upload(bytes, "exr", lights(2), "map.exr").asset->id;
    ASSERT_NE(one, two);
    const std::string map_file = "environments/" + api::sha256_hex(bytes) + ".exr";

    EXPECT_TRUE(environments_->remove(one));
    const auto other = environments_->find(two);
    ASSERT_NE(other, nullptr);
    EXPECT_NE(environments_->source_image(*other), nullptr);
    EXPECT_EQ(stored_files(), (std::vector<std::string>{map_file, "rig-sources/" + two + ".sealed",
                                                        "rigs/" + two + ".sealed"}));
    EXPECT_TRUE(environments_->remove(two));
    EXPECT_TRUE(stored_files().empty());
}

TEST_F(EnvironmentRegistryTest, ThePresetIsNeitherListedNorRemoved) {
    EXPECT_FALSE(environments_->remove(std::string(api::kDefaultPresetId)));
    EXPECT_NE(environments_->find(std::string(api::kDefaultPresetId)), nullptr);
    EXPECT_TRUE(listed_ids().empty());
    EXPECT_FALSE(environments_->remove("../../etc/passwd"));
}

// remove() takes the cube and the rig first, then the record (the commit), then the map. A crash
// before the record went leaves an environment that is served whole (its rig, and its cube when
// a frame needs it, recomputed); one after it, none, whatever files are left.
TEST_F(EnvironmentRegistryTest, ACrashBeforeTheRecordWentLeavesTheEnvironmentWhole) {
    const std::string bytes = map_bytes(40.0f);
    const auto uploaded = environments_->upload(bytes, "exr", lights(2), "map.exr").asset;
    ASSERT_TRUE(store_.remove(DerivedKind::Rig, uploaded->id));
    restart();
    EXPECT_EQ(listed_ids(), std::vector<std::string>{uploaded->id});
    const auto found = environments_->find(uploaded->id);
    ASSERT_NE(found, nullptr);
    nlohmann::json expected = uploaded->json, got = found->json;
    expected.erase("timings_ms");
    got.erase("timings_ms");
    EXPECT_EQ(got, expected);
}

TEST_F(EnvironmentRegistryTest, ACrashAfterTheRecordWentLeavesNoEnvironment) {
    const std::string bytes = map_bytes(40.0f);
    const auto uploaded = environments_->upload(bytes, "exr", lights(2), "map.exr").asset;
    ASSERT_TRUE(store_.remove(DerivedKind::RigSource, uploaded->id));
    restart();
    EXPECT_TRUE(listed_ids().empty());
    EXPECT_EQ(environments_->find(uploaded->id), nullptr);
    // Deleting it again answers that it is gone and takes what the crash left of it, but the
    // map, which no record names any more (the next upload of the same bytes uses it).
    EXPECT_FALSE(environments_->remove(uploaded->id));
    EXPECT_EQ(stored_files(),
              std::vector<std::string>{"environments/" + api::sha256_hex(bytes) + ".exr"});
}

TEST_F(EnvironmentRegistryTest, ListPagesByIdWithEachMapsSizeFormatAndTime) {
    const auto before = std::chrono::system_clock::now() - std::chrono::seconds(2);
    std::map<std::string, std::string> map_of;  // rig id -> map bytes
    for (const float brightness : {40.0f, 50.0f}) {
        const std::string bytes = map_bytes(brightness);
        for (const int count : {1, 2}) {
            map_of[environments_->upload(bytes, "exr", lights(count), "map.exr").asset->id] = bytes;
        }
    }
    const auto after = std::chrono::system_clock::now() + std::chrono::seconds(2);
    ASSERT_EQ(map_of.size(), 4u);

    std::vector<std::string> walked;
    std::string cursor;
    int pages = 0;
    for (;; ++pages) {
        const ListedPage page = environments_->list(cursor, 3);
        for (const ListedAsset& entry : page.entries) {
            SCOPED_TRACE(entry.id);
            walked.push_back(entry.id);
            ASSERT_TRUE(map_of.count(entry.id));
            EXPECT_EQ(entry.source_id, api::sha256_hex(map_of[entry.id]));
            ASSERT_TRUE(entry.source.has_value());
            EXPECT_EQ(entry.source->bytes, map_of[entry.id].size());
            EXPECT_EQ(entry.source->extension, "exr");
            EXPECT_GT(entry.stored, before);
            EXPECT_LT(entry.stored, after);
        }
        if (!page.next_after) {
            break;
        }
        EXPECT_EQ(*page.next_after, page.entries.back().id);
        cursor = *page.next_after;
    }
    EXPECT_EQ(pages + 1, 2);
    std::vector<std::string> expected;
    for (const auto& [id, bytes] : map_of) {
        expected.push_back(id);
    }
    EXPECT_EQ(walked, expected) << "every environment once, in ascending order of id";
}

// Removals landing at every moment of an upload that computes the rig: afterwards memory, the
// listing and the store agree. Without the store lock a removal could take the record the
// upload had just written and forget the rig in memory before the upload remembered it, so
// that the rig was served while the store no longer had it.
TEST_F(EnvironmentRegistryTest, RemovalsRacingUploadsLeaveMemoryAndStoreInAgreement) {
    const std::string bytes = map_bytes(40.0f);
    const auto start = std::chrono::steady_clock::now();
    const std::string id = environments_->upload(bytes, "exr", lights(2), "map.exr").asset->id;
    const auto upload_time = std::chrono::steady_clock::now() - start;
    constexpr int kRounds = 40;
    for (int round = 0; round < kRounds; ++round) {
        SCOPED_TRACE(round);
        environments_->remove(id);
        std::thread upload([&] { environments_->upload(bytes, "exr", lights(2), "map.exr"); });
        std::this_thread::sleep_for(upload_time * round / kRounds);
        environments_->remove(id);
        upload.join();
        const bool found = environments_->find(id) != nullptr;
        const bool recorded = store_.contains(DerivedKind::RigSource, id);
        EXPECT_EQ(found, recorded);
        EXPECT_EQ(listed_ids().size(), recorded ? 1u : 0u);
        if (recorded) {
            EXPECT_TRUE(store_.contains(DerivedKind::Rig, id));
            EXPECT_TRUE(store_.contains(SourceKind::Environment, api::sha256_hex(bytes)));
        } else {
            EXPECT_TRUE(stored_files().empty());
        }
    }
}
