#include "oer/server/asset_store.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <iterator>
#include <set>
#include <utility>

#include "oer/api/content_id.hpp"
#include "oer/core/error.hpp"
#include "quoted_excerpt.hpp"

namespace oer::server {

namespace fs = std::filesystem;

namespace {

constexpr std::array<std::string_view, 7> kEnvironmentExtensions{"exr",  "hdr", "png", "jpg",
                                                                 "jpeg", "tif", "tiff"};
constexpr std::array<std::string_view, 3> kMeshExtensions{"glb", "gltf", "obj"};
constexpr std::string_view kTemporaryPrefix = ".tmp-";
constexpr std::string_view kSealMagic = "oer-sealed-v1";

std::string_view folder_name(SourceKind kind) {
    return kind == SourceKind::Environment ? "environments" : "meshes";
}

std::string_view folder_name(DerivedKind kind) {
    switch (kind) {
        case DerivedKind::Rig:
            return "rigs";
        case DerivedKind::RigSource:
            return "rig-sources";
        case DerivedKind::Specular:
            return "specular";
        case DerivedKind::Transfer:
            return "transfer";
        case DerivedKind::TransferMeshes:
            return "transfer-meshes";
        case DerivedKind::MeshSummary:
            return "mesh-summaries";
    }
    throw Error(ErrorKind::Internal, "asset store: unknown derived kind");
}

std::string_view kind_name(SourceKind kind) {
    return kind == SourceKind::Environment ? "environment" : "mesh";
}

[[noreturn]] void throw_io(const std::string& action, const fs::path& path, int error) {
    throw Error(ErrorKind::Io, "asset store: cannot " + action + " " + path.string() + ": " +
                                   std::strerror(error));
}

// throw_io, but StorageFull when the file system is full or the quota used up: entry says what
// could not be stored, without the path.
[[noreturn]] void throw_write_failure(const std::string& action, const fs::path& path, int error,
                                      const std::string& entry) {
    if (error == ENOSPC || error == EDQUOT) {
        throw StorageFull(
            entry, std::strerror(error),
            "asset store: cannot " + action + " " + path.string() + ": " + std::strerror(error));
    }
    throw_io(action, path, error);
}

// What a client may be told a write was for: the entry's kind and id.
std::string entry_name(SourceKind kind, std::string_view id) {
    return std::string(kind == SourceKind::Environment ? "the map " : "the mesh ") +
           std::string(id);
}

std::string entry_name(DerivedKind kind, std::string_view id) {
    switch (kind) {
        case DerivedKind::Rig:
            return "the rig " + std::string(id);
        case DerivedKind::RigSource:
            return "the record of rig " + std::string(id);
        case DerivedKind::Specular:
            return "the specular cube of rig " + std::string(id);
        case DerivedKind::Transfer:
            return "the transfer " + std::string(id);
        case DerivedKind::TransferMeshes:
            return "the record of transfer " + std::string(id);
        case DerivedKind::MeshSummary:
            return "the summary of mesh " + std::string(id);
    }
    throw Error(ErrorKind::Internal, "asset store: unknown derived kind");
}

void check_id(std::string_view id) {
    if (!is_asset_id(id)) {
        throw Error(ErrorKind::InvalidInput,
                    "asset id must be 64 lowercase hexadecimal digits, got " + quoted_excerpt(id));
    }
}

// Closes a descriptor on every path out of a scope.
class FileDescriptor {
  public:
    explicit FileDescriptor(int fd) : fd_(fd) {}
    FileDescriptor(const FileDescriptor&) = delete;
    FileDescriptor& operator=(const FileDescriptor&) = delete;
    ~FileDescriptor() {
        if (fd_ >= 0) {
            ::close(fd_);
        }
    }
    int get() const { return fd_; }
    // close() reports write-back errors that fsync() may not have, so it is checked.
    int close() { return ::close(std::exchange(fd_, -1)); }

  private:
    int fd_;
};

void fsync_folder(const fs::path& folder) {
    const FileDescriptor fd(::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
    if (fd.get() < 0 || ::fsync(fd.get()) != 0) {
        throw_io("flush folder", folder, errno);
    }
}

}  // namespace

// Writes bytes to a new temporary file beside path, flushes it, renames it over path and
// flushes the folder, so that path holds either its old content or all of bytes. entry names
// what is written, for StorageFull.
void write_file_atomically(const fs::path& path, std::string_view bytes, const std::string& entry) {
    std::string temporary = (path.parent_path() /
                             (std::string(kTemporaryPrefix) + path.filename().string() + "-XXXXXX"))
                                .string();
    FileDescriptor fd(::mkostemp(temporary.data(), O_CLOEXEC));
    if (fd.get() < 0) {
        throw_write_failure("create a temporary file for", path, errno, entry);
    }
    try {
        for (std::size_t done = 0; done < bytes.size();) {
            const ssize_t written = ::write(fd.get(), bytes.data() + done, bytes.size() - done);
            if (written < 0 && errno != EINTR) {
                throw_write_failure("write", temporary, errno, entry);
            }
            done += std::size_t(std::max<ssize_t>(written, 0));
        }
        if (::fsync(fd.get()) != 0) {
            throw_write_failure("flush", temporary, errno, entry);
        }
        if (fd.close() != 0) {
            throw_write_failure("close", temporary, errno, entry);
        }
        if (::rename(temporary.c_str(), path.c_str()) != 0) {
            throw_write_failure("rename " + temporary + " to", path, errno, entry);
        }
    } catch (...) {
        ::unlink(temporary.c_str());
        throw;
    }
    fsync_folder(path.parent_path());
}

namespace {

// The whole file, or nullopt if it does not exist.
std::optional<std::string> read_file(const fs::path& path) {
    const FileDescriptor fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
    if (fd.get() < 0) {
        if (errno == ENOENT) {
            return std::nullopt;
        }
        throw_io("open", path, errno);
    }
    struct stat status {};
    if (::fstat(fd.get(), &status) != 0) {
        throw_io("inspect", path, errno);
    }
    std::string bytes(std::size_t(status.st_size), '\0');
    std::size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t got = ::read(fd.get(), bytes.data() + done, bytes.size() - done);
        if (got < 0 && errno != EINTR) {
            throw_io("read", path, errno);
        }
        if (got == 0) {
            break;  // the file shrank since fstat: what was read is what there is
        }
        done += std::size_t(std::max<ssize_t>(got, 0));
    }
    bytes.resize(done);
    return bytes;
}

// Removes path and flushes its folder, so that the removal survives a crash as a write does.
bool remove_file(const fs::path& path) {
    if (::unlink(path.c_str()) != 0) {
        if (errno != ENOENT) {
            throw_io("remove", path, errno);
        }
        return false;
    }
    fsync_folder(path.parent_path());
    return true;
}

// The size and time of writing of a file, or nullopt if it does not exist.
std::optional<StoredEntryInfo> file_info(const fs::path& path, std::string extension) {
    struct stat status {};
    if (::stat(path.c_str(), &status) != 0) {
        if (errno == ENOENT) {
            return std::nullopt;
        }
        throw_io("inspect", path, errno);
    }
    const auto since_epoch = std::chrono::seconds(status.st_mtim.tv_sec) +
                             std::chrono::nanoseconds(status.st_mtim.tv_nsec);
    return StoredEntryInfo{
        std::uintmax_t(status.st_size), std::move(extension),
        std::chrono::system_clock::time_point(
            std::chrono::duration_cast<std::chrono::system_clock::duration>(since_epoch))};
}

// The smallest `limit` ids after `after` among the files of folder named <id>.<extension>
// with an extension `accepts`; temporary files and other names are not entries.
template <typename Accepts>
std::vector<std::string> list_folder(const fs::path& folder, std::string_view after,
                                     std::size_t limit, Accepts accepts) {
    if (!after.empty()) {
        check_id(after);
    }
    std::set<std::string> smallest;
    std::error_code error;
    for (const fs::directory_entry& entry : fs::directory_iterator(folder, error)) {
        const std::string name = entry.path().filename().string();
        const std::size_t dot = name.find('.');
        if (dot == std::string::npos || !is_asset_id(std::string_view(name).substr(0, dot)) ||
            !accepts(std::string_view(name).substr(dot + 1))) {
            continue;
        }
        std::string id = name.substr(0, dot);
        // compare(), not <=: clang 14 cannot compile libstdc++ 12's string <=> string_view.
        if (id.compare(after) <= 0 || limit == 0) {
            continue;
        }
        if (smallest.size() == limit) {
            if (id >= *smallest.rbegin()) {
                continue;
            }
            smallest.erase(std::prev(smallest.end()));
        }
        smallest.insert(std::move(id));
    }
    if (error) {
        throw_io("list", folder, error.value());
    }
    return {smallest.begin(), smallest.end()};
}

std::string seal(std::string_view payload) {
    return std::string(kSealMagic) + " " + api::sha256_hex(payload) + " " +
           std::to_string(payload.size()) + "\n" + std::string(payload);
}

// The payload of a sealed entry, or what is wrong with it.
struct Unsealed {
    std::optional<std::string> payload;
    std::string problem;
};

Unsealed unseal(const std::string& entry) {
    const auto newline = entry.find('\n');
    const std::string_view header = std::string_view(entry).substr(0, newline);
    const std::string prefix = std::string(kSealMagic) + " ";
    if (newline == std::string::npos || !header.starts_with(prefix) ||
        header.size() < prefix.size() + 64 + 2 || header[prefix.size() + 64] != ' ') {
        return {std::nullopt, "its header line is missing or malformed"};
    }
    const std::string_view digest = header.substr(prefix.size(), 64);
    const std::string_view length_text = header.substr(prefix.size() + 65);
    std::size_t length = 0;
    const auto [end, error] =
        std::from_chars(length_text.data(), length_text.data() + length_text.size(), length);
    if (error != std::errc() || end != length_text.data() + length_text.size()) {
        return {std::nullopt, "its header line is missing or malformed"};
    }
    std::string payload = entry.substr(newline + 1);
    if (payload.size() != length) {
        return {std::nullopt, "its payload is " + std::to_string(payload.size()) +
                                  " bytes, its header says " + std::to_string(length)};
    }
    if (api::sha256_hex(payload) != digest) {
        return {std::nullopt, "its payload does not match its SHA-256"};
    }
    return {std::move(payload), ""};
}

}  // namespace

bool is_asset_id(std::string_view text) {
    return text.size() == 64 && std::all_of(text.begin(), text.end(), [](char c) {
               return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f');
           });
}

std::span<const std::string_view> allowed_extensions(SourceKind kind) {
    if (kind == SourceKind::Environment) {
        return kEnvironmentExtensions;
    }
    return kMeshExtensions;
}

AssetStore::AssetStore(fs::path folder, Log log)
    : folder_(std::move(folder)), log_(std::move(log)) {
    int writes_in_progress = 0;
    for (const std::string_view name :
         {folder_name(SourceKind::Environment), folder_name(SourceKind::Mesh),
          folder_name(DerivedKind::Rig), folder_name(DerivedKind::RigSource),
          folder_name(DerivedKind::Specular), folder_name(DerivedKind::Transfer),
          folder_name(DerivedKind::TransferMeshes), folder_name(DerivedKind::MeshSummary)}) {
        const fs::path kind_folder = folder_ / name;
        std::error_code error;
        fs::create_directories(kind_folder, error);
        if (error) {
            throw Error(ErrorKind::Io, "asset store: cannot create folder " + kind_folder.string() +
                                           ": " + error.message());
        }
        for (const fs::directory_entry& entry : fs::directory_iterator(kind_folder, error)) {
            if (!entry.path().filename().string().starts_with(kTemporaryPrefix)) {
                continue;
            }
            const auto written = file_info(entry.path(), "");
            if (!written) {
                continue;  // renamed or removed since it was listed: another process's
            }
            const auto untouched = std::chrono::system_clock::now() - written->written;
            if (untouched < kAbandonedTemporaryAge) {
                ++writes_in_progress;
                continue;
            }
            remove_file(entry.path());
            log_("asset store: removed " + entry.path().string() +
                 ", left by an interrupted write (untouched for " +
                 std::to_string(
                     std::chrono::duration_cast<std::chrono::minutes>(untouched).count()) +
                 " min)");
        }
        if (error) {
            throw Error(ErrorKind::Io, "asset store: cannot list folder " + kind_folder.string() +
                                           ": " + error.message());
        }
    }
    if (writes_in_progress > 0) {
        log_("asset store: left " + std::to_string(writes_in_progress) +
             " temporary file(s) modified in the last " +
             std::to_string(kAbandonedTemporaryAge.count()) +
             " min: writes in progress, perhaps by another process sharing the folder (removed "
             "at a later start if abandoned)");
    }
}

std::string AssetStore::put_source(SourceKind kind, std::string_view bytes,
                                   std::string_view extension) {
    const auto allowed = allowed_extensions(kind);
    if (std::find(allowed.begin(), allowed.end(), extension) == allowed.end()) {
        std::string list;
        for (const std::string_view name : allowed) {
            list += (list.empty() ? "" : ", ") + std::string(name);
        }
        throw Error(ErrorKind::Unsupported, "asset store: " + std::string(kind_name(kind)) +
                                                " extension must be one of " + list + "; got " +
                                                quoted_excerpt(extension));
    }
    std::string id = api::sha256_hex(bytes);
    const fs::path path = folder_ / folder_name(kind) / (id + "." + std::string(extension));
    const std::lock_guard lock(lock_for(id));
    if (const auto existing = find_source(kind, id); existing && *existing != path) {
        throw Error(ErrorKind::InvalidInput,
                    "asset store: these bytes are already stored as " +
                        std::string(kind_name(kind)) + " " + existing->filename().string() +
                        "; the same bytes cannot also be a ." + std::string(extension));
    }
    write_file_atomically(path, bytes, entry_name(kind, id));
    return id;
}

std::optional<StoredSource> AssetStore::get_source(SourceKind kind, std::string_view id) {
    check_id(id);
    const std::lock_guard lock(lock_for(id));
    const auto path = find_source(kind, id);
    if (!path) {
        return std::nullopt;
    }
    auto bytes = read_file(*path);
    if (!bytes) {
        return std::nullopt;
    }
    if (api::sha256_hex(*bytes) != id) {
        drop_corrupt(*path, "its bytes no longer hash to its id");
        return std::nullopt;
    }
    return StoredSource{std::move(*bytes), path->extension().string().substr(1)};
}

void AssetStore::put_derived(DerivedKind kind, std::string_view id, std::string_view bytes) {
    check_id(id);
    const fs::path path = derived_path(kind, id);
    const std::string entry = seal(bytes);
    const std::lock_guard lock(lock_for(id));
    write_file_atomically(path, entry, entry_name(kind, id));
}

bool AssetStore::put_derived_if_room(DerivedKind kind, std::string_view id,
                                     std::string_view bytes) {
    try {
        put_derived(kind, id, bytes);
        return true;
    } catch (const StorageFull& full) {
        log_(std::string(full.what()) + "; " + full.entry() +
             " is kept in memory only (computed again after a restart)");
        return false;
    }
}

std::optional<std::string> AssetStore::get_derived(DerivedKind kind, std::string_view id) {
    check_id(id);
    const fs::path path = derived_path(kind, id);
    const std::lock_guard lock(lock_for(id));
    const auto entry = read_file(path);
    if (!entry) {
        return std::nullopt;
    }
    Unsealed unsealed = unseal(*entry);
    if (!unsealed.payload) {
        drop_corrupt(path, unsealed.problem);
    }
    return std::move(unsealed.payload);
}

bool AssetStore::contains(SourceKind kind, std::string_view id) const {
    check_id(id);
    return find_source(kind, id).has_value();
}

bool AssetStore::contains(DerivedKind kind, std::string_view id) const {
    check_id(id);
    std::error_code error;
    const bool found = fs::exists(derived_path(kind, id), error);
    if (error) {
        throw_io("inspect", derived_path(kind, id), error.value());
    }
    return found;
}

bool AssetStore::remove(SourceKind kind, std::string_view id) {
    check_id(id);
    const std::lock_guard lock(lock_for(id));
    const auto path = find_source(kind, id);
    return path && remove_file(*path);
}

bool AssetStore::remove(DerivedKind kind, std::string_view id) {
    check_id(id);
    const std::lock_guard lock(lock_for(id));
    return remove_file(derived_path(kind, id));
}

std::vector<std::string> AssetStore::list(SourceKind kind, std::string_view after,
                                          std::size_t limit) const {
    const auto allowed = allowed_extensions(kind);
    return list_folder(
        folder_ / folder_name(kind), after, limit, [&allowed](std::string_view extension) {
            return std::find(allowed.begin(), allowed.end(), extension) != allowed.end();
        });
}

std::vector<std::string> AssetStore::list(DerivedKind kind, std::string_view after,
                                          std::size_t limit) const {
    return list_folder(folder_ / folder_name(kind), after, limit,
                       [](std::string_view extension) { return extension == "sealed"; });
}

std::optional<StoredEntryInfo> AssetStore::info(SourceKind kind, std::string_view id) const {
    check_id(id);
    const auto path = find_source(kind, id);
    return path ? file_info(*path, path->extension().string().substr(1)) : std::nullopt;
}

std::optional<StoredEntryInfo> AssetStore::info(DerivedKind kind, std::string_view id) const {
    check_id(id);
    return file_info(derived_path(kind, id), "sealed");
}

std::optional<fs::path> AssetStore::find_source(SourceKind kind, std::string_view id) const {
    for (const std::string_view extension : allowed_extensions(kind)) {
        fs::path path =
            folder_ / folder_name(kind) / (std::string(id) + "." + std::string(extension));
        std::error_code error;
        if (fs::exists(path, error)) {
            return path;
        }
        if (error) {
            throw_io("inspect", path, error.value());
        }
    }
    return std::nullopt;
}

fs::path AssetStore::derived_path(DerivedKind kind, std::string_view id) const {
    return folder_ / folder_name(kind) / (std::string(id) + ".sealed");
}

std::mutex& AssetStore::lock_for(std::string_view id) {
    unsigned index = 0;
    std::from_chars(id.data(), id.data() + 2, index, 16);
    return id_locks_[index];
}

void AssetStore::drop_corrupt(const fs::path& path, const std::string& reason) {
    remove_file(path);
    log_("asset store: removed corrupt " + path.string() + ": " + reason);
}

}  // namespace oer::server
