// Uploaded meshes listed and removed, from the store and from memory; the preset stays.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "mesh_registry.hpp"
#include "oer/api/content_id.hpp"
#include "oer/core/error.hpp"
#include "oer/server/metrics.hpp"

using namespace oer;
using namespace oer::server;
namespace fs = std::filesystem;

namespace {

// A tetrahedron of the given size, as OBJ text.
std::string tetrahedron_obj(int size) {
    const std::string s = std::to_string(size);
    return "v 0 0 0\nv " + s + " 0 0\nv 0 " + s + " 0\nv 0 0 " + s +
           "\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
}

class MeshRegistryTest : public ::testing::Test {
  protected:
    MeshRegistryTest()
        : folder_(fs::temp_directory_path() /
                  ("oer-mesh-registry-test-" + std::to_string(::getpid()) + "-" +
                   ::testing::UnitTest::GetInstance()->current_test_info()->name())),
          store_(folder_, [](std::string_view) {}),
          metrics_(registry_),
          meshes_(store_, metrics_, budget_, MeshLimits{}, 64 << 20) {}
    ~MeshRegistryTest() override { fs::remove_all(folder_); }

    const fs::path folder_;
    AssetStore store_;
    MetricsRegistry registry_;
    ServiceMetrics metrics_;
    UploadBudget budget_{UploadBudgetLimits{}};
    MeshRegistry meshes_;
};

}  // namespace

TEST_F(MeshRegistryTest, RemoveTakesTheFileAndForgetsTheMesh) {
    const std::string bytes = tetrahedron_obj(1);
    const auto uploaded = meshes_.upload(bytes, MeshFormat::Obj, "box.obj").asset;
    ASSERT_NE(meshes_.find(uploaded->id), nullptr);
    ASSERT_TRUE(store_.contains(SourceKind::Mesh, uploaded->id));

    EXPECT_TRUE(meshes_.remove(uploaded->id));
    EXPECT_FALSE(store_.contains(SourceKind::Mesh, uploaded->id));
    EXPECT_EQ(meshes_.find(uploaded->id), nullptr) << "still in memory";
    EXPECT_TRUE(meshes_.list("", 10).entries.empty());
    EXPECT_FALSE(meshes_.remove(uploaded->id));
    EXPECT_EQ(uploaded->mesh->primitives.size(), 1u) << "a frame that held it keeps it whole";
    EXPECT_FALSE(meshes_.upload(bytes, MeshFormat::Obj, "box.obj").cached)
        << "uploaded again, loaded again";
}

TEST_F(MeshRegistryTest, ThePresetIsNeitherListedNorRemoved) {
    EXPECT_FALSE(meshes_.remove(std::string(api::kDefaultPresetId)));
    EXPECT_NE(meshes_.find(std::string(api::kDefaultPresetId)), nullptr);
    EXPECT_TRUE(meshes_.list("", 10).entries.empty());
}

TEST_F(MeshRegistryTest, ListPagesByIdWithEachFilesSizeAndFormat) {
    std::map<std::string, std::string> bytes_of;
    for (int size = 1; size <= 5; ++size) {
        const std::string bytes = tetrahedron_obj(size);
        bytes_of[meshes_.upload(bytes, MeshFormat::Obj, "box.obj").asset->id] = bytes;
    }
    const ListedPage first = meshes_.list("", 3);
    ASSERT_EQ(first.entries.size(), 3u);
    ASSERT_TRUE(first.next_after.has_value());
    const ListedPage second = meshes_.list(*first.next_after, 3);
    ASSERT_EQ(second.entries.size(), 2u);
    EXPECT_FALSE(second.next_after.has_value());
    try {
        meshes_.list("", 0);
        ADD_FAILURE() << "a page of no entries";
    } catch (const Error& error) {
        EXPECT_EQ(error.kind(), ErrorKind::Internal);
    }
    auto expected = bytes_of.begin();
    for (const ListedPage* page : {&first, &second}) {
        for (const ListedAsset& entry : page->entries) {
            EXPECT_EQ(entry.id, expected->first);
            EXPECT_EQ(entry.source_id, entry.id);
            ASSERT_TRUE(entry.source.has_value());
            EXPECT_EQ(entry.source->bytes, expected->second.size());
            EXPECT_EQ(entry.source->extension, "obj");
            ++expected;
        }
    }
}
