#include "btf/archive.h"

#include <zip.h>

#include <algorithm>
#include <cctype>

#include "core/error.h"
#include "core/fs.h"

namespace inlight::btf {

namespace {

zip_t* handle(void* z) { return static_cast<zip_t*>(z); }

std::string error_text(int code) {
    zip_error_t e;
    zip_error_init_with_code(&e, code);
    std::string text = zip_error_strerror(&e);
    zip_error_fini(&e);
    return text;
}

}  // namespace

bool is_zip_path(const std::string& path) {
    if (path.size() < 4) return false;
    std::string ext = path.substr(path.size() - 4);
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext == ".zip";
}

std::unique_ptr<ZipArchive> ZipArchive::open(const std::string& path) {
    std::unique_ptr<ZipArchive> a(new ZipArchive());
    a->m_name = path;
    fs::check_input_file(path);
    int code = 0;
    a->m_zip = zip_open(path.c_str(), ZIP_RDONLY, &code);
    if (!a->m_zip) throw Error(str(path, ": cannot open as a zip archive: ", error_text(code)));
    a->list();
    return a;
}

std::unique_ptr<ZipArchive> ZipArchive::open_memory(const void* data, size_t size,
                                                    const std::string& name) {
    std::unique_ptr<ZipArchive> a(new ZipArchive());
    a->m_name = name;
    a->m_buffer.assign(static_cast<const char*>(data), size);
    zip_error_t err;
    zip_error_init(&err);
    zip_source_t* src = zip_source_buffer_create(a->m_buffer.data(), a->m_buffer.size(), 0, &err);
    if (!src) {
        const std::string text = zip_error_strerror(&err);
        zip_error_fini(&err);
        throw Error(str(name, ": cannot read as a zip archive: ", text));
    }
    a->m_zip = zip_open_from_source(src, ZIP_RDONLY, &err);
    if (!a->m_zip) {
        zip_source_free(src);
        const std::string text = zip_error_strerror(&err);
        zip_error_fini(&err);
        throw Error(str(name, ": cannot read as a zip archive: ", text));
    }
    zip_error_fini(&err);
    a->list();
    return a;
}

ZipArchive::~ZipArchive() {
    if (m_zip) zip_discard(handle(m_zip));
}

void ZipArchive::list() {
    const zip_int64_t n = zip_get_num_entries(handle(m_zip), 0);
    if (n < 0) throw Error(str(m_name, ": cannot list the archive"));
    m_entries.reserve(static_cast<size_t>(n));
    for (zip_int64_t i = 0; i < n; ++i) {
        zip_stat_t st;
        zip_stat_init(&st);
        if (zip_stat_index(handle(m_zip), static_cast<zip_uint64_t>(i), 0, &st) != 0 ||
            !(st.valid & ZIP_STAT_NAME) || !(st.valid & ZIP_STAT_SIZE)) {
            throw Error(str(m_name, ": entry ", i, " has no readable name or size"));
        }
        ArchiveEntry e;
        e.name = st.name;
        e.size = st.size;
        e.index = static_cast<uint64_t>(i);
        e.is_directory = !e.name.empty() && e.name.back() == '/';
        m_entries.push_back(std::move(e));
    }
}

std::string ZipArchive::read(const ArchiveEntry& entry, uint64_t max_bytes) const {
    const uint64_t want = std::min(entry.size, max_bytes);
    if (want > max_entry_bytes) {
        throw Error(str(m_name, ":", entry.name, ": entry of ", entry.size,
                        " bytes is larger than the limit of ", max_entry_bytes, " bytes"));
    }
    std::lock_guard<std::mutex> lock(m_mutex);
    zip_file_t* f = zip_fopen_index(handle(m_zip), entry.index, 0);
    if (!f) {
        throw Error(
            str(m_name, ":", entry.name, ": cannot open entry: ", zip_strerror(handle(m_zip))));
    }
    std::string bytes(static_cast<size_t>(want), '\0');
    uint64_t got = 0;
    while (got < want) {
        const zip_int64_t r = zip_fread(f, bytes.data() + got, want - got);
        if (r < 0) {
            const std::string text = zip_file_strerror(f);
            zip_fclose(f);
            throw Error(str(m_name, ":", entry.name, ": cannot read entry: ", text));
        }
        if (r == 0) break;
        got += static_cast<uint64_t>(r);
    }
    zip_fclose(f);
    if (got != want) {
        throw Error(
            str(m_name, ":", entry.name, ": entry is truncated (", got, " of ", want, " bytes)"));
    }
    return bytes;
}

}  // namespace inlight::btf
