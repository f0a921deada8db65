// core/fs.h: outputs that appear whole or not at all. Every file is written to a temporary
// sibling and renamed; inside a run (app::run) every output of the run is staged that way and
// all are renamed together only when the whole run succeeds (OutputTransaction).
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace inlight::fs {

/// A sibling path for a temporary file that keeps the extension, so format detection by
/// extension still works: "out/sky.exr" -> "out/sky.tmp-<pid>-<n>.exr".
std::string temp_sibling(const std::string& path);

/// When a file written by write_atomic becomes visible under its name.
enum class Commit {
    kWithRun,  ///< with the run's other outputs, when the run succeeds (immediately outside a run)
    kNow,      ///< immediately: only for files inside a private temporary tree that the caller
               ///< moves into place itself (e.g. a bundle folder written under a hidden name)
};

/// Calls write(tmp_path) for a temporary sibling of `path`, then renames it onto `path`, now
/// or, inside an OutputTransaction, when the run commits. If write throws, the temporary file is
/// removed and the exception propagates; `path` is never left partially written. Creates the
/// parent directory if it does not exist. Inside a transaction, throws UsageError if `path`
/// resolves to an input of the run or to another output of it.
void write_atomic(const std::string& path, const std::function<void(const std::string&)>& write,
                  Commit commit = Commit::kWithRun);

/// Writes text (or bytes) atomically. Throws Error naming the file on failure.
void write_text_atomic(const std::string& path, const std::string& content,
                       Commit commit = Commit::kWithRun);

/// Checks that `path` is a file a reader can read to its end: it exists and is a regular file
/// (after symlinks). A folder, a FIFO, a device (/dev/zero, /dev/stdin), or a socket throws Error
/// naming the path and what it is: reading /dev/zero or a FIFO never ends, and was a hang.
void check_input_file(const std::string& path);

/// What kind of thing `path` is when it exists but is not a regular file or a folder ("a FIFO",
/// "a character device", ...), or "" (a regular file, a folder, or nothing at all).
std::string special_file_kind(const std::string& path);

/// Reads a whole file (check_input_file first). Throws Error naming the file if it cannot be read.
std::string read_file(const std::string& path);

/// The file name's extension in lower case without the dot ("EXR" -> "exr"), or "".
std::string extension(const std::string& path);

/// Removes, under `dir` (recursively), the temporary siblings (temp_sibling's "<stem>.tmp-<pid>-
/// <n><ext>") that a process no longer running left behind: a run killed before it could commit
/// or roll back (SIGKILL, power loss). A live process's temporaries, including this one's, are
/// kept. Returns how many were removed; never throws (an unreadable folder removes nothing).
size_t remove_stale_temporaries(const std::string& dir);

/// Whether two paths name the same file: the same path once symlinks, "." and ".." are resolved,
/// or (when both exist) the same device and inode (hard links).
bool same_file(const std::string& a, const std::string& b);

/// Checks an output stem (a tool's -o to which it appends ".bin", "_stderr.exr", ...): throws
/// UsageError naming `what` if it has no file name ("", "out/", "out/.", ".."), as
/// such a stem wrote hidden files like "out/.bin".
void check_output_stem(const std::string& stem, const std::string& what);

/// Declares an input of the current run (no-op outside one). Throws UsageError naming both if it
/// is the same file as a declared output. Report::add_input calls this for every input.
void declare_input(const std::string& path, const std::string& what = "");
/// Declares an output of the current run before any work (no-op outside one). Throws UsageError
/// naming both if it is the same file as an input or as another declared output.
void declare_output(const std::string& path, const std::string& what = "");

/// The outputs of one run: every write_atomic(Commit::kWithRun) while it is current is staged as
/// a temporary sibling; commit() renames them all into place, rollback() (or the destructor
/// without commit) removes them and the directories the run created, so a failed run leaves
/// the output folders exactly as they were. Before staging, each output is checked against the
/// run's inputs and other outputs. One transaction at a time per process (app::run owns it);
/// thread-safe.
class OutputTransaction {
  public:
    OutputTransaction();
    ~OutputTransaction();
    OutputTransaction(const OutputTransaction&) = delete;
    OutputTransaction& operator=(const OutputTransaction&) = delete;

    /// The transaction of the running tool, or nullptr.
    static OutputTransaction* current();

    void add_input(const std::string& path, const std::string& what);
    void add_output(const std::string& path, const std::string& what);
    /// A path that is neither input nor output but must not be either (the --report file).
    void reserve(const std::string& path, const std::string& what);
    /// Whether `path` is the same file as a declared input.
    bool is_input(const std::string& path) const;
    /// Why an input or output of the run was refused because it is the file of a reserved path
    /// (the --report file), e.g. "it is an input of the run", or "": the report must then not be
    /// written there either.
    std::string reserved_clash() const;

    /// Stages a write of `path`: checks it, creates its parent directories (remembered for
    /// rollback) and returns the temporary path to write. The caller writes it, then either
    /// keeps it staged or calls unstage(path) on failure.
    std::string stage(const std::string& path);
    void unstage(const std::string& path);

    /// Renames every staged file into place, in the order staged. Throws Error if a rename
    /// fails (the remaining temporaries are removed; the message names what was already moved).
    void commit();
    /// Removes every staged file and the directories created for them. Never throws.
    void rollback() noexcept;
    /// For a process about to end on a signal (call it, then _Exit): takes the transaction's lock
    /// for good, so no further output can be staged, and removes every staged file and created
    /// directory twice, `grace_s` apart, because a writer that had its temporary path before
    /// the lock may still be creating that file after the first pass. Never throws.
    void abandon(double grace_s) noexcept;
    /// Number of staged files.
    size_t staged_count() const;

  private:
    struct Entry {
        std::string path, what;  ///< as given, and the option or role that named it
        std::string key;         ///< the path resolved when it was added (same_file's first test)
    };
    struct Staged {
        std::string path, tmp;
    };
    /// The entry naming the same file as `path` (resolved to `key`), as fs::same_file decides:
    /// the same resolved path, or the same (device, inode). Entries keep their resolved path, so
    /// a run staging thousands of outputs resolves each new one once, not every entry again.
    const Entry* find_same(const std::vector<Entry>& list, const std::string& path,
                           const std::string& key) const;

    mutable std::mutex m_mutex;
    std::vector<Entry> m_inputs, m_outputs, m_reserved;
    std::vector<Staged> m_staged;
    /// The staged paths resolved, and the (device, inode) of those that existed when staged:
    /// stage() checks a new output against them in O(log n), so a run may stage thousands of
    /// files (a BTF capture writes 6561) without a quadratic scan of the file system.
    std::map<std::string, std::string> m_staged_by_path;
    std::map<std::pair<uint64_t, uint64_t>, std::string> m_staged_by_inode;
    std::vector<std::string> m_created_dirs;  ///< deepest last
    bool m_done = false;
    std::string m_reserved_clash;
};

}  // namespace inlight::fs
