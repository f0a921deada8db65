// btf/archive.h: read-only access to zip archives (libzip), so Bonn's distributed BTF zip files
// are read in place, entry by entry, without unpacking them to disk.
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace inlight::btf {

/// One file in an archive.
struct ArchiveEntry {
    std::string name;    ///< path inside the archive, '/'-separated ("tv030_pv090/x.png")
    uint64_t size = 0;   ///< uncompressed bytes
    uint64_t index = 0;  ///< libzip index
    bool is_directory = false;
};

/// A zip archive opened read-only. Reads are serialised by an internal mutex (libzip's archive
/// handle is not thread-safe), so one ZipArchive may be shared by worker threads; decoding what
/// was read can run in parallel. Entries larger than `max_entry_bytes` are refused (zip bombs).
class ZipArchive {
  public:
    /// Opens a zip file. Throws Error naming the file when it is missing or not a zip archive.
    static std::unique_ptr<ZipArchive> open(const std::string& path);
    /// Opens a zip archive held in memory (the bytes are copied); `name` names it in errors.
    static std::unique_ptr<ZipArchive> open_memory(const void* data, size_t size,
                                                   const std::string& name);
    ~ZipArchive();
    ZipArchive(const ZipArchive&) = delete;
    ZipArchive& operator=(const ZipArchive&) = delete;

    const std::string& name() const { return m_name; }
    const std::vector<ArchiveEntry>& entries() const { return m_entries; }

    /// The first `max_bytes` bytes (all, when the entry is shorter) of an entry. Throws Error
    /// naming the archive and entry on a read or CRC failure, or when the entry is larger than
    /// max_entry_bytes and more than that is asked for.
    std::string read(const ArchiveEntry& entry, uint64_t max_bytes = UINT64_MAX) const;

    /// Entries larger than this (uncompressed) are refused: 1 GiB by default.
    uint64_t max_entry_bytes = uint64_t(1) << 30;

  private:
    ZipArchive() = default;
    void list();
    std::string m_name;
    std::string m_buffer;   // the archive's bytes when opened from memory
    void* m_zip = nullptr;  // zip_t*
    std::vector<ArchiveEntry> m_entries;
    mutable std::mutex m_mutex;
};

/// True when the path names a zip file by its extension (".zip", any case).
bool is_zip_path(const std::string& path);

}  // namespace inlight::btf
