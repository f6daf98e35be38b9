// SIGHUP and the bake file: relightd re-reads its bake when the file changed
// since it was loaded (a new bake renamed over it, or the file rewritten in
// place), and takes it only when it is whole and valid and has the same
// luminaires in the same order (the patch, the replay and the DMX patch are
// bound to them by index). Anything else leaves the running bake as it is:
// a truncated copy or a half-written file never takes a show down.
//
// Thread safety: one thread (the daemon's).
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <string>

#include "relight/engine/engine.h"

namespace relight::daemon {

// What identifies the file last loaded: device, inode, size, mtime.
struct BakeFileId {
  dev_t dev = 0;
  ino_t ino = 0;
  off_t size = -1;
  int64_t mtime_ns = -1;
  bool operator==(const BakeFileId& o) const {
    return dev == o.dev && ino == o.ino && size == o.size && mtime_ns == o.mtime_ns;
  }
};

// The file's id now; size -1 when it cannot be stat'ed.
BakeFileId StatBakeFile(const std::string& path);

enum class BakeReload { kUnchanged, kTaken };

// Re-reads `path` when its id differs from `*loaded`. On a valid bake with
// the same luminaires: the engine opens it, every luminaire keeps its state
// (pan, tilt, dimmer, colour, roll, zoom), `*loaded` becomes the new id and
// kTaken is returned. kUnchanged: the file is the one loaded. An error
// (kNotFound, kIoError, kCorrupt, kUnsupported from ReadBake;
// kInvalidArgument for other luminaires) names the file and what is wrong;
// the engine and `*loaded` are untouched. The new bake opens with `options`
// (the ones the running bake was opened with); `force` reads it even if it
// is the file loaded (the options changed).
Status ReloadBake(const std::string& path, Engine* engine, BakeFileId* loaded, BakeReload* result,
                  const EngineOptions& options = {}, bool force = false);

}  // namespace relight::daemon
