#pragma once
// Uploaded assets and what is derived from them, kept as files in a data folder so that they
// survive restarts. Sources (environment maps, meshes) are content-addressed: their id is the
// SHA-256 of their bytes. Derived entries (rigs) are stored under an id the caller computes
// (a rig's id hashes its source and its options), sealed with a checksum of their payload.
//
// Layout: DIR/environments/<id>.<ext>, DIR/meshes/<id>.<ext> (the upload's bytes as they came,
// the extension naming their format), DIR/rigs/<id>.sealed, DIR/rig-sources/<id>.sealed and
// DIR/specular/<rig id>.sealed, DIR/transfer/<scene's transfer id>.sealed,
// DIR/transfer-meshes/<transfer id>.sealed, DIR/mesh-summaries/<mesh id>.sealed (a header line
// "oer-sealed-v1 <sha256 of payload> <payload length>\n", then the payload).
//
// Writes are atomic: a uniquely named temporary file beside the entry is written, flushed to
// disk, renamed over the entry, and the folder flushed, so a crash leaves either the old entry
// or the new one, never part of one. Reads are checked: a source whose bytes no longer hash to
// its id, or a sealed entry whose payload does not match its header, is logged, deleted and
// reported absent, so the caller recomputes it (or asks for the upload again) instead of
// serving damaged data. Ids are validated before any path is built from them.
//
// Removals mirror the writes: one file goes at once (unlink), and the folder is flushed before
// remove() returns, so a removal that was acknowledged stays done after a crash, as a write
// does. An entry made of several files is removed by its owner in an order where every state a
// crash can leave is the whole entry or none (EnvironmentRegistry::remove).
//
// A write that fails because the file system is full (ENOSPC) or the data folder's quota is used
// up (EDQUOT) throws StorageFull and leaves nothing behind (its temporary file is removed), so
// the same write succeeds once space is freed.
//
// Thread-safe: operations on one id are serialised (by a lock chosen from the id), operations
// on different ids mostly run in parallel.
//
// Several processes may share one data folder (replicas behind a balancer, on one machine or
// on a shared volume: docker/README.md), with no lock between them. What makes that safe:
// - Every entry appears whole or not at all: its temporary file is renamed over it, and
//   rename(2) within one directory of one file system replaces the name atomically (POSIX: a
//   reader opens the old file or the new one, never a mix). Both names are in the entry's own
//   folder, so the rename never crosses file systems. A reader holding the old file keeps
//   reading it whole after the rename (its descriptor holds the old inode).
// - Temporary names are unique across processes: mkostemp creates the file with O_EXCL under a
//   random suffix, so two writers never write into one temporary file.
// - Concurrent writers of one id write the same bytes: a source's id is the SHA-256 of its
//   bytes, and a derived entry's id hashes everything it is computed from (a rig's: its map and
//   options; a transfer's: its scene), so whichever rename lands last, the entry holds the
//   bytes every writer meant. The one exception, the same bytes uploaded under two extensions
//   at once through two processes (the check against it is per process), stores both files,
//   which hold the same bytes: either serves.
// - Reads check what they read (a source against its id, a sealed entry against its header),
//   so an entry damaged by anything (a torn write of a file system without atomic rename, a
//   disk) is dropped and recomputed, never served.
// - The start-up sweep of temporary files spares any modified in the last
//   kAbandonedTemporaryAge (below): another process's write in progress keeps its file's
//   modification time fresh, so a process that starts or restarts never removes it.
// What is NOT guaranteed across processes:
// - A removal through one process is not seen by another's caches in memory (decoded assets,
//   rigs, frames): that one serves the removed entry until it evicts it, and a later lookup of
//   it on disk finds nothing (404).
// - A removal racing an upload of the same entry through another process (the per-process
//   locks of the registries order them only within one process) can leave a partial set of
//   files: a rig without its record of provenance (unlisted, never served: a lookup starts
//   from the record), a record and rig whose map went (listed with no source; frames that need
//   the map, a specular cube or a preview, cannot compute it until the map is uploaded again,
//   which restores it), or a map no rig uses (unlisted). Each is either whole enough to serve
//   correctly or not served, because every file is whole and checked on read and every id
//   names one content; uploading the same bytes again makes the entry whole.
// - A corrupt entry dropped by one process's read may take with it a good copy that another
//   process renamed over it in between (the unlink is by name): then the entry is absent and is
//   computed again, or uploaded again.
#include <array>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "oer/core/error.hpp"
#include "oer/server/log_line.hpp"

namespace oer::server {

enum class SourceKind { Environment, Mesh };
// Rig: a preprocessed rig (its JSON and its light masks). RigSource: which source and options a
// rig came from, kept apart so that a damaged rig can be recomputed from its source. Specular:
// a rig's residual map prefiltered (oer::encode_prefiltered_cube), by the rig's id. Transfer: a
// scene's precomputed radiance transfer (oer::encode_transfer), by an id hashing everything its
// bake depends on. TransferMeshes: the meshes a stored transfer's scene holds, by the transfer's
// id (so that it goes with any of them). MeshSummary: what a render needs to know of a stored
// mesh before it decodes it (its counts and its textures' decoded bytes), by the mesh's id.
enum class DerivedKind { Rig, RigSource, Specular, Transfer, TransferMeshes, MeshSummary };

struct StoredSource {
    std::string bytes;
    std::string extension;  // as given to put_source, e.g. "glb"
};

// What a listing shows of a stored entry.
struct StoredEntryInfo {
    std::uintmax_t bytes = 0;  // of the file: a source's own bytes, a derived entry's sealed form
    std::string extension;     // a source's, as given to put_source; "sealed" for derived entries
    std::chrono::system_clock::time_point written;  // when the entry was last written
};

// A write refused for want of space (ENOSPC) or quota (EDQUOT): an oer::Error of kind Io whose
// message, for the log, names the file; entry() names what could not be stored without any
// path ("the map 3f2a...", "the rig 9c01..."), and reason() is the system's words
// ("No space left on device"), for an answer to a client.
class StorageFull : public Error {
  public:
    StorageFull(std::string entry, std::string reason, const std::string& message)
        : Error(ErrorKind::Io, message), entry_(std::move(entry)), reason_(std::move(reason)) {}
    const std::string& entry() const { return entry_; }
    const std::string& reason() const { return reason_; }

  private:
    std::string entry_;
    std::string reason_;
};

// Exactly 64 lowercase hexadecimal digits (a SHA-256 in hex), the only ids the store accepts.
bool is_asset_id(std::string_view text);

// How long a temporary file must have gone unmodified before the store's start-up removes it as
// abandoned. A write in progress modifies its temporary file at every write(2), and its bytes
// are all in memory before the file is made, so it never waits for a client between two
// writes; the longest it leaves the file unmodified is its fsync and rename at the end, seconds
// at worst on a slow shared volume (256 MiB, the largest upload, at 50 MB/s: 5 s). Ten minutes
// is a hundred times that, and covers the clock skew between machines that share a network
// volume (the file's time is the file server's, the comparison is with this machine's clock).
// A write stalled longer than that (its process stopped, its volume frozen) loses its file: its
// rename fails, and the upload or computation reports the error instead of storing anything.
inline constexpr std::chrono::minutes kAbandonedTemporaryAge{10};

// Writes bytes to path as the store writes its entries: a new temporary file beside it (named
// with the store's temporary prefix, so that a crash's leftover is swept at start-up),
// flushed, renamed over path, the folder flushed; path then holds its old content or all of
// bytes. entry names what is written, for StorageFull. For the job store's files too.
void write_file_atomically(const std::filesystem::path& path, std::string_view bytes,
                           const std::string& entry);

// Lowercase, without the dot: environments exr, hdr, png, jpg, jpeg, tif, tiff;
// meshes glb, gltf, obj.
std::span<const std::string_view> allowed_extensions(SourceKind kind);

class AssetStore {
  public:
    using Log = std::function<void(std::string_view line)>;

    // Creates the folder and its sub-folders if missing, and removes the temporary files that
    // an interrupted write left behind: those not modified for kAbandonedTemporaryAge (younger
    // ones may be another process's writes in progress: they are counted in one log line and
    // left). Failures throw oer::Error (Io). Corrupt entries and removed temporary files are
    // reported to log, one line each.
    explicit AssetStore(std::filesystem::path folder, Log log = log_line);

    const std::filesystem::path& folder() const { return folder_; }

    // Stores the bytes (again, if already there) and returns their id. An extension not allowed
    // for the kind throws oer::Error (Unsupported); the same bytes already stored under another
    // extension throw oer::Error (InvalidInput).
    std::string put_source(SourceKind kind, std::string_view bytes, std::string_view extension);
    // nullopt when absent, or when the entry was corrupt (then it is logged and deleted). Reads
    // and hashes the whole entry, so hot assets belong in a ByteLruCache in front of the store.
    std::optional<StoredSource> get_source(SourceKind kind, std::string_view id);

    void put_derived(DerivedKind kind, std::string_view id, std::string_view bytes);
    // put_derived for an entry that can be computed again when missing (a specular cube, a
    // transfer, a rig recomputed from its source): when the disk is full it logs that the entry
    // is kept in memory only and returns false instead of throwing StorageFull, so that a frame
    // is not refused for want of room to keep what it computed. Other failures throw.
    bool put_derived_if_room(DerivedKind kind, std::string_view id, std::string_view bytes);
    // nullopt when absent, or when the entry was corrupt (then it is logged and deleted).
    std::optional<std::string> get_derived(DerivedKind kind, std::string_view id);

    // Whether an entry is on disk; cheap, so unchecked: only a get verifies the bytes.
    bool contains(SourceKind kind, std::string_view id) const;
    bool contains(DerivedKind kind, std::string_view id) const;

    // true if there was an entry; durable when it returns (the folder is flushed).
    bool remove(SourceKind kind, std::string_view id);
    bool remove(DerivedKind kind, std::string_view id);

    // The ids of kind's entries in ascending order: those after `after` (every id when empty),
    // at most limit of them. Memory and time grow with limit and the folder's size, never with
    // more than limit ids at once. Unchecked, like contains().
    std::vector<std::string> list(SourceKind kind, std::string_view after, std::size_t limit) const;
    std::vector<std::string> list(DerivedKind kind, std::string_view after,
                                  std::size_t limit) const;

    // The entry's size, extension and time of writing, or nullopt when absent.
    std::optional<StoredEntryInfo> info(SourceKind kind, std::string_view id) const;
    std::optional<StoredEntryInfo> info(DerivedKind kind, std::string_view id) const;

    // Every operation taking an id throws oer::Error (InvalidInput) for one that is not
    // is_asset_id, and every operation throws oer::Error (Io) when the file system fails.

  private:
    std::optional<std::filesystem::path> find_source(SourceKind kind, std::string_view id) const;
    std::filesystem::path derived_path(DerivedKind kind, std::string_view id) const;
    std::mutex& lock_for(std::string_view id);
    void drop_corrupt(const std::filesystem::path& path, const std::string& reason);

    const std::filesystem::path folder_;
    const Log log_;
    std::array<std::mutex, 256> id_locks_;  // chosen by an id's first two hex digits
};

}  // namespace oer::server
