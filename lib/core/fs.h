// core/fs.h: outputs that appear whole or not at all (write to a temporary sibling, then rename).
#pragma once

#include <functional>
#include <string>

namespace inlight::fs {

/// A sibling path for a temporary file that keeps the extension, so format detection by
/// extension still works: "out/sky.exr" -> "out/sky.tmp-<pid>-<n>.exr".
std::string temp_sibling(const std::string& path);

/// Calls write(tmp_path), then renames tmp_path onto path. If write throws, the temporary file
/// is removed and the exception propagates; `path` is never left partially written.
/// Creates the parent directory if it does not exist.
void write_atomic(const std::string& path, const std::function<void(const std::string&)>& write);

/// Writes text (or bytes) atomically. Throws Error naming the file on failure.
void write_text_atomic(const std::string& path, const std::string& content);

/// Reads a whole file. Throws Error naming the file if it cannot be read.
std::string read_file(const std::string& path);

/// The file name's extension in lower case without the dot ("EXR" -> "exr"), or "".
std::string extension(const std::string& path);

}  // namespace inlight::fs
