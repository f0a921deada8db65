// Tests of core/fs.h's run-wide OutputTransaction: outputs appear together or not at all, a
// failed run leaves its output folders exactly as they were, and no output may be an input or
// another output (same path after resolution, symlink or hard link).
#include "core/fs.h"

#include <sys/wait.h>
#include <unistd.h>

#include <csignal>

#include <filesystem>
#include <map>

#include <gtest/gtest.h>

#include "core/error.h"
#include "testing/testing.h"

namespace inlight {
namespace {

namespace stdfs = std::filesystem;

/// Every file and folder below `dir` with its content ("<dir>" for folders).
std::map<std::string, std::string> listing(const std::string& dir) {
    std::map<std::string, std::string> out;
    for (const auto& e : stdfs::recursive_directory_iterator(dir)) {
        const std::string rel = stdfs::relative(e.path(), dir).string();
        out[rel] = e.is_directory() ? "<dir>" : fs::read_file(e.path().string());
    }
    return out;
}

TEST(RemoveStaleTemporaries, RemovesOnlyThoseOfProcessesThatAreGone) {
    const std::string dir = testing::temp_dir("stale_tmp");
    // A process that has ended: its pid names no process until the kernel reuses it.
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) _exit(0);
    ASSERT_EQ(waitpid(child, nullptr, 0), child);
    const std::string dead = std::to_string(child), mine = std::to_string(getpid());
    fs::write_text_atomic(dir + "/a.tmp-" + dead + "-0.png", "x");
    fs::write_text_atomic(dir + "/view/b c.tmp-" + dead + "-17.exr", "x");  // nested, spaces
    fs::write_text_atomic(dir + "/d.tmp-" + dead + "-3", "x");              // no extension
    fs::write_text_atomic(dir + "/e.tmp-" + mine + "-1.png", "x");          // this process's
    fs::write_text_atomic(dir + "/f.png", "x");
    fs::write_text_atomic(dir + "/g.tmp-x-1.png", "x");                     // not a pid
    const size_t removed = fs::remove_stale_temporaries(dir);
    if (kill(child, 0) == 0) GTEST_SKIP() << "pid " << child << " was reused at once";
    EXPECT_EQ(removed, 3u);
    EXPECT_EQ(listing(dir), (std::map<std::string, std::string>{{"e.tmp-" + mine + "-1.png", "x"},
                                                               {"f.png", "x"},
                                                               {"g.tmp-x-1.png", "x"},
                                                               {"view", "<dir>"}}));
    EXPECT_EQ(fs::remove_stale_temporaries(dir + "/absent"), 0u);
}

TEST(OutputTransaction, FailedRunLeavesTheFolderAsItWas) {
    const std::string dir = testing::temp_dir("txn_rollback");
    fs::write_text_atomic(dir + "/old.txt", "old");
    const auto before = listing(dir);
    {
        fs::OutputTransaction txn;
        fs::write_text_atomic(dir + "/a.txt", "a");
        fs::write_text_atomic(dir + "/new/sub/b.txt", "b");  // creates two folders
        fs::write_text_atomic(dir + "/old.txt", "new");
        EXPECT_EQ(txn.staged_count(), 3u);
        // Staged, not visible: the old file is untouched, the new ones are absent.
        EXPECT_EQ(fs::read_file(dir + "/old.txt"), "old");
        EXPECT_FALSE(stdfs::exists(dir + "/a.txt"));
        EXPECT_FALSE(stdfs::exists(dir + "/new/sub/b.txt"));
        txn.rollback();
    }
    EXPECT_EQ(listing(dir), before);  // no temporaries, no created folders
    {
        fs::OutputTransaction txn;
        fs::write_text_atomic(dir + "/a.txt", "a");
        // A writer that fails: its temporary goes, the other staged output stays staged.
        EXPECT_THROW(fs::write_atomic(dir + "/c.txt", [](const std::string&) { throw Error("x"); }),
                     Error);
        EXPECT_EQ(txn.staged_count(), 1u);
    }  // destroyed without commit: rolled back
    EXPECT_EQ(listing(dir), before);
}

TEST(OutputTransaction, CommitMovesEveryOutputIntoPlace) {
    const std::string dir = testing::temp_dir("txn_commit");
    fs::write_text_atomic(dir + "/old.txt", "old");
    {
        fs::OutputTransaction txn;
        fs::write_text_atomic(dir + "/a.txt", "a");
        fs::write_text_atomic(dir + "/new/b.txt", "b");
        fs::write_text_atomic(dir + "/old.txt", "new");
        // Commit::kNow bypasses staging (a caller's own private temporary tree).
        fs::write_text_atomic(dir + "/now.txt", "now", fs::Commit::kNow);
        EXPECT_EQ(fs::read_file(dir + "/now.txt"), "now");
        txn.commit();
    }
    const std::map<std::string, std::string> expect = {
        {"a.txt", "a"}, {"new", "<dir>"}, {"new/b.txt", "b"}, {"old.txt", "new"}, {"now.txt", "now"}};
    EXPECT_EQ(listing(dir), expect);
}

TEST(OutputTransaction, RefusesOutputsThatAreInputs) {
    const std::string dir = testing::temp_dir("txn_inputs");
    fs::write_text_atomic(dir + "/in.png", "pixels");
    ASSERT_EQ(::link((dir + "/in.png").c_str(), (dir + "/hard.png").c_str()), 0);
    stdfs::create_symlink(dir + "/in.png", dir + "/soft.png");
    fs::OutputTransaction txn;
    fs::declare_input(dir + "/in.png", "--images");
    for (const std::string& out :
         {dir + "/in.png", dir + "/./sub/../in.png", dir + "/hard.png", dir + "/soft.png"}) {
        const std::string msg = testing::error_of([&] { fs::declare_output(out, "-o"); });
        EXPECT_NE(msg.find(str("output '", out, "' (-o) is the input '", dir, "/in.png' (--images)")),
                  std::string::npos)
            << msg;
        // Undeclared outputs are checked when written, and nothing is staged.
        EXPECT_THROW(fs::write_text_atomic(out, "x"), UsageError) << out;
    }
    EXPECT_EQ(txn.staged_count(), 0u);
    // An input named after its output was declared is refused too.
    fs::declare_output(dir + "/out.exr", "-o");
    EXPECT_THROW(fs::declare_input(dir + "/out.exr", "scene environment"), UsageError);
    txn.rollback();
    EXPECT_EQ(fs::read_file(dir + "/in.png"), "pixels");
}

TEST(OutputTransaction, RefusesAnOutputBelowAnExistingFile) {
    // render export-gles SCENE -o scene.toml: the folder is an existing file. Refused when declared,
    // before any work, naming the option and the file (it failed only when writing, at the end).
    const std::string dir = testing::temp_dir("txn_below_file");
    fs::write_text_atomic(dir + "/scene.toml", "x");
    fs::OutputTransaction txn;
    const std::string msg = testing::error_of(
        [&] { fs::declare_output(dir + "/scene.toml/sub/index.json", "--export-gles"); });
    EXPECT_NE(msg.find(str("(--export-gles) needs the folder '", dir,
                           "/scene.toml', which is an existing file")),
              std::string::npos)
        << msg;
    fs::declare_output(dir + "/new/sub/index.json", "--export-gles");  // missing folders are fine
    txn.rollback();
    EXPECT_EQ(fs::read_file(dir + "/scene.toml"), "x");
}

TEST(OutputTransaction, RefusesTwoOutputsThatAreOneFile) {
    const std::string dir = testing::temp_dir("txn_outputs");
    fs::OutputTransaction txn;
    fs::declare_output(dir + "/x.exr", "-o");
    const std::string msg =
        testing::error_of([&] { fs::declare_output(dir + "/sub/../x.exr", "--stderr-output"); });
    EXPECT_NE(msg.find(str("outputs '", dir, "/x.exr' (-o) and '", dir,
                           "/sub/../x.exr' (--stderr-output) are the same file")),
              std::string::npos)
        << msg;
    fs::write_text_atomic(dir + "/y.json", "1");
    EXPECT_THROW(fs::write_text_atomic(dir + "/./y.json", "2"), UsageError);
    txn.reserve(dir + "/report.json", "--report");
    EXPECT_THROW(fs::write_text_atomic(dir + "/report.json", "3"), UsageError);
}

TEST(Fs, SameFile) {
    const std::string dir = testing::temp_dir("same_file");
    fs::write_text_atomic(dir + "/a", "a");
    fs::write_text_atomic(dir + "/b", "a");
    EXPECT_TRUE(fs::same_file(dir + "/a", dir + "/../" + stdfs::path(dir).filename().string() + "/a"));
    EXPECT_FALSE(fs::same_file(dir + "/a", dir + "/b"));  // equal content, different files
    EXPECT_FALSE(fs::same_file(dir + "/a", dir + "/missing"));
    EXPECT_TRUE(fs::same_file(dir + "/missing/../x", dir + "/x"));
}

}  // namespace
}  // namespace inlight
