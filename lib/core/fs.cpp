#include "core/fs.h"

#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <atomic>
#include <cctype>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <thread>

#include "core/check.h"
#include "core/error.h"

namespace inlight::fs {
namespace {

namespace stdfs = std::filesystem;

std::atomic<OutputTransaction*> g_current{nullptr};

/// The path with symlinks, "." and ".." resolved as far as it exists.
stdfs::path resolved(const std::string& path) {
    std::error_code ec;
    const stdfs::path abs = stdfs::absolute(path, ec);
    if (ec) return stdfs::path(path).lexically_normal();
    const stdfs::path c = stdfs::weakly_canonical(abs, ec);
    return ec ? abs.lexically_normal() : c;
}

std::string shown(const std::string& path, const std::string& what) {
    return what.empty() ? str("'", path, "'") : str("'", path, "' (", what, ")");
}

}  // namespace

std::string temp_sibling(const std::string& path) {
    static std::atomic<int> counter{0};
    const stdfs::path p(path);
    const std::string tag = str(".tmp-", ::getpid(), "-", counter++);
    return (p.parent_path() / (p.stem().string() + tag + p.extension().string())).string();
}

size_t remove_stale_temporaries(const std::string& dir) {
    static const std::regex kTemp(R"(.*\.tmp-([0-9]+)-[0-9]+(\.[^./]*)?)");
    size_t removed = 0;
    std::error_code ec;
    for (stdfs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        std::smatch m;
        const std::string name = it->path().filename().string();
        if (!std::regex_match(name, m, kTemp) || !it->is_regular_file(ec)) continue;
        const long pid = std::strtol(m[1].str().c_str(), nullptr, 10);
        // kill(pid, 0) fails with ESRCH when no such process exists.
        if (pid <= 0 || pid == ::getpid() || ::kill(static_cast<pid_t>(pid), 0) == 0 ||
            errno != ESRCH)
            continue;
        std::error_code rm;
        if (stdfs::remove(it->path(), rm)) ++removed;
    }
    return removed;
}

bool same_file(const std::string& a, const std::string& b) {
    if (resolved(a) == resolved(b)) return true;
    struct stat sa {};
    struct stat sb {};
    return ::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0 && sa.st_dev == sb.st_dev &&
           sa.st_ino == sb.st_ino;
}

void write_atomic(const std::string& path, const std::function<void(const std::string&)>& write,
                  Commit commit) {
    if (OutputTransaction* txn = commit == Commit::kWithRun ? OutputTransaction::current() : nullptr) {
        const std::string tmp = txn->stage(path);
        try {
            write(tmp);
        } catch (...) {
            txn->unstage(path);
            throw;
        }
        return;
    }
    const stdfs::path parent = stdfs::path(path).parent_path();
    std::error_code ec;
    if (!parent.empty()) {
        stdfs::create_directories(parent, ec);
        if (ec) throw Error(str(path, ": cannot create directory ", parent, ": ", ec.message()));
    }
    const std::string tmp = temp_sibling(path);
    try {
        write(tmp);
    } catch (...) {
        stdfs::remove(tmp, ec);
        throw;
    }
    stdfs::rename(tmp, path, ec);
    if (ec) {
        stdfs::remove(tmp, ec);
        throw Error(str(path, ": cannot move the finished file into place"));
    }
}

void write_text_atomic(const std::string& path, const std::string& content, Commit commit) {
    write_atomic(
        path,
        [&](const std::string& tmp) {
            std::ofstream out(tmp, std::ios::binary);
            out.write(content.data(), static_cast<std::streamsize>(content.size()));
            out.close();
            if (!out) throw Error(str(path, ": write failed"));
        },
        commit);
}

std::string special_file_kind(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) return "";
    if (S_ISREG(st.st_mode) || S_ISDIR(st.st_mode)) return "";
    if (S_ISFIFO(st.st_mode)) return "a FIFO (named pipe)";
    if (S_ISCHR(st.st_mode)) return "a character device";
    if (S_ISBLK(st.st_mode)) return "a block device";
    if (S_ISSOCK(st.st_mode)) return "a socket";
    return "not a regular file";
}

void check_input_file(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) {
        throw Error(str(path, ": cannot open: ", std::strerror(errno)));
    }
    if (S_ISDIR(st.st_mode)) throw Error(str(path, ": is a folder, not a file"));
    if (!S_ISREG(st.st_mode)) {
        throw Error(str(path, ": is ", special_file_kind(path), ", not a regular file"));
    }
}

std::string read_file(const std::string& path) {
    check_input_file(path);
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(str(path, ": cannot open for reading"));
    std::ostringstream ss;
    ss << in.rdbuf();
    if (in.bad()) throw Error(str(path, ": read failed"));
    return ss.str();
}

std::string extension(const std::string& path) {
    std::string ext = stdfs::path(path).extension().string();
    if (!ext.empty() && ext[0] == '.') ext.erase(0, 1);
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext;
}

void check_output_stem(const std::string& stem, const std::string& what) {
    const stdfs::path p(stem);
    const std::string name = p.filename().string();
    if (name.empty() || name == "." || name == "..") {
        throw UsageError(str(what, " '", stem, "': names a folder, not a file stem (the outputs "
                             "are STEM.ext; give e.g. out/satin)"));
    }
}

void declare_input(const std::string& path, const std::string& what) {
    if (OutputTransaction* txn = OutputTransaction::current()) txn->add_input(path, what);
}

void declare_output(const std::string& path, const std::string& what) {
    if (OutputTransaction* txn = OutputTransaction::current()) txn->add_output(path, what);
}

// --- OutputTransaction -------------------------------------------------------------------------

OutputTransaction::OutputTransaction() {
    OutputTransaction* expected = nullptr;
    const bool installed = g_current.compare_exchange_strong(expected, this);
    INLIGHT_CHECK(installed) << "one OutputTransaction at a time";
}

OutputTransaction::~OutputTransaction() {
    if (!m_done) rollback();
    g_current.store(nullptr);
}

OutputTransaction* OutputTransaction::current() { return g_current.load(); }

const OutputTransaction::Entry* OutputTransaction::find_same(const std::vector<Entry>& list,
                                                             const std::string& path,
                                                             const std::string& key) const {
    struct stat sp {};
    int have_path = -1;  // stat'ed once, when an entry's key differs
    for (const Entry& e : list) {
        if (e.key == key) return &e;
        if (have_path < 0) have_path = ::stat(path.c_str(), &sp) == 0 ? 1 : 0;
        struct stat se {};
        if (have_path == 1 && ::stat(e.path.c_str(), &se) == 0 && se.st_dev == sp.st_dev &&
            se.st_ino == sp.st_ino)
            return &e;
    }
    return nullptr;
}

void OutputTransaction::add_input(const std::string& path, const std::string& what) {
    std::lock_guard<std::mutex> lock(m_mutex);
    const std::string key = resolved(path).string();
    for (const auto* list : {&m_outputs, &m_reserved}) {
        if (const Entry* o = find_same(*list, path, key)) {
            if (list == &m_reserved) m_reserved_clash = "it is an input of the run";
            throw UsageError(str("output ", shown(o->path, o->what), " is the input ",
                                 shown(path, what), ": the run would overwrite its input"));
        }
    }
    for (const Staged& s : m_staged) {
        if (same_file(s.path, path)) {
            throw UsageError(str("output '", s.path, "' is the input ", shown(path, what),
                                 ": the run would overwrite its input"));
        }
    }
    if (!find_same(m_inputs, path, key)) m_inputs.push_back({path, what, key});
}

void OutputTransaction::add_output(const std::string& path, const std::string& what) {
    std::lock_guard<std::mutex> lock(m_mutex);
    const std::string key = resolved(path).string();
    if (const Entry* i = find_same(m_inputs, path, key)) {
        throw UsageError(str("output ", shown(path, what), " is the input ", shown(i->path, i->what),
                             ": the run would overwrite its input"));
    }
    for (const auto* list : {&m_outputs, &m_reserved}) {
        if (const Entry* o = find_same(*list, path, key)) {
            if (list == &m_reserved) m_reserved_clash = "it is also an output of the run";
            throw UsageError(str("outputs ", shown(o->path, o->what), " and ", shown(path, what),
                                 " are the same file: one would overwrite the other"));
        }
    }
    std::error_code ec;
    if (stdfs::is_directory(path, ec)) {
        throw UsageError(str("output ", shown(path, what), " is an existing folder, not a file"));
    }
    // A folder the output needs that exists as a file (e.g. --export-gles naming the scene file):
    // found now, before any work, not when the write fails at the end of the run.
    for (stdfs::path p = stdfs::path(path).parent_path(); !p.empty(); p = p.parent_path()) {
        if (stdfs::exists(p, ec)) {
            if (!stdfs::is_directory(p, ec)) {
                throw UsageError(str("output ", shown(path, what), " needs the folder '", p.string(),
                                     "', which is an existing file"));
            }
            break;
        }
        if (p == p.parent_path()) break;
    }
    m_outputs.push_back({path, what, key});
}

void OutputTransaction::reserve(const std::string& path, const std::string& what) {
    add_output(path, what);
    std::lock_guard<std::mutex> lock(m_mutex);
    m_reserved.push_back(m_outputs.back());
    m_outputs.pop_back();
}

bool OutputTransaction::is_input(const std::string& path) const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return find_same(m_inputs, path, resolved(path).string()) != nullptr;
}

std::string OutputTransaction::stage(const std::string& path) {
    std::lock_guard<std::mutex> lock(m_mutex);
    INLIGHT_CHECK(!m_done) << "staging after commit or rollback: " << path;
    const std::string key = resolved(path).string();
    if (const Entry* i = find_same(m_inputs, path, key)) {
        throw UsageError(str("output '", path, "' is the input ", shown(i->path, i->what),
                             ": the run would overwrite its input"));
    }
    if (const Entry* r = find_same(m_reserved, path, key)) {
        m_reserved_clash = "it is also an output of the run";
        throw UsageError(str("output '", path, "' is the file of ", shown(r->path, r->what)));
    }
    struct stat st {};
    const bool exists = ::stat(path.c_str(), &st) == 0;
    const std::pair<uint64_t, uint64_t> inode(st.st_dev, st.st_ino);
    const auto by_path = m_staged_by_path.find(key);
    const auto by_inode = exists ? m_staged_by_inode.find(inode) : m_staged_by_inode.end();
    if (by_path != m_staged_by_path.end() || by_inode != m_staged_by_inode.end()) {
        const std::string& other =
            by_path != m_staged_by_path.end() ? by_path->second : by_inode->second;
        throw UsageError(str("two outputs of this run are the same file: '", other, "' and '",
                             path, "'"));
    }
    {
        std::error_code ec;
        if (stdfs::is_directory(path, ec)) {
            throw UsageError(str("output '", path, "' is an existing folder, not a file"));
        }
    }
    // Create the missing parent directories, remembering them (outermost first) for rollback.
    std::vector<stdfs::path> missing;
    for (stdfs::path p = stdfs::path(path).parent_path(); !p.empty(); p = p.parent_path()) {
        std::error_code ec;
        if (stdfs::exists(p, ec)) break;
        missing.push_back(p);
        if (p == p.parent_path()) break;
    }
    for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
        std::error_code ec;
        stdfs::create_directory(*it, ec);
        if (ec) throw Error(str(path, ": cannot create directory ", *it, ": ", ec.message()));
        m_created_dirs.push_back(it->string());
    }
    m_staged.push_back({path, temp_sibling(path)});
    m_staged_by_path.emplace(key, path);
    if (exists) m_staged_by_inode.emplace(inode, path);
    return m_staged.back().tmp;
}

void OutputTransaction::unstage(const std::string& path) {
    std::lock_guard<std::mutex> lock(m_mutex);
    for (auto it = m_staged.begin(); it != m_staged.end(); ++it) {
        if (it->path == path) {
            std::error_code ec;
            stdfs::remove(it->tmp, ec);
            m_staged.erase(it);
            m_staged_by_path.erase(resolved(path).string());
            for (auto i = m_staged_by_inode.begin(); i != m_staged_by_inode.end(); ++i) {
                if (i->second == path) {
                    m_staged_by_inode.erase(i);
                    break;
                }
            }
            return;
        }
    }
}

void OutputTransaction::commit() {
    std::lock_guard<std::mutex> lock(m_mutex);
    INLIGHT_CHECK(!m_done) << "commit twice";
    m_done = true;
    // Pre-flight: anything that would make a rename fail is found before the first rename.
    for (const Staged& s : m_staged) {
        std::error_code ec;
        if (stdfs::is_directory(s.path, ec) || !stdfs::exists(s.tmp, ec)) {
            for (const Staged& t : m_staged) stdfs::remove(t.tmp, ec);
            throw Error(str(s.path, ": cannot move the finished file into place (",
                            stdfs::is_directory(s.path, ec) ? "a folder is in the way"
                                                            : "its temporary file is gone",
                            "); no output was written"));
        }
    }
    std::vector<std::string> moved;
    for (size_t i = 0; i < m_staged.size(); ++i) {
        std::error_code ec;
        stdfs::rename(m_staged[i].tmp, m_staged[i].path, ec);
        if (ec) {
            for (size_t k = i; k < m_staged.size(); ++k) stdfs::remove(m_staged[k].tmp, ec);
            std::string done;
            for (const std::string& m : moved) done += (done.empty() ? "" : ", ") + m;
            throw Error(str(m_staged[i].path, ": cannot move the finished file into place (",
                            ec.message(), ")", moved.empty() ? "" : "; already in place: ", done));
        }
        moved.push_back(m_staged[i].path);
    }
    m_staged.clear();
}

void OutputTransaction::rollback() noexcept {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_done = true;
    std::error_code ec;
    for (const Staged& s : m_staged) stdfs::remove(s.tmp, ec);
    m_staged.clear();
    // Deepest first; a directory that is not empty (someone else wrote there) stays.
    for (auto it = m_created_dirs.rbegin(); it != m_created_dirs.rend(); ++it) stdfs::remove(*it, ec);
    m_created_dirs.clear();
}

void OutputTransaction::abandon(double grace_s) noexcept {
    m_mutex.lock();  // never released: the process ends right after
    m_done = true;
    for (int pass = 0; pass < 2; ++pass) {
        if (pass == 1) std::this_thread::sleep_for(std::chrono::duration<double>(grace_s));
        std::error_code ec;
        for (const Staged& s : m_staged) stdfs::remove(s.tmp, ec);
        for (auto it = m_created_dirs.rbegin(); it != m_created_dirs.rend(); ++it)
            stdfs::remove(*it, ec);
    }
}

std::string OutputTransaction::reserved_clash() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_reserved_clash;
}

size_t OutputTransaction::staged_count() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_staged.size();
}

}  // namespace inlight::fs
