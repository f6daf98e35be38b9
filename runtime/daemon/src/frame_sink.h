// Where relightd's frames go. A sink takes each finished 8-bit RGB frame
// (top row first) and writes it somewhere: a PNG sequence, a PPM or raw
// stream on stdout or a FIFO, a Linux framebuffer device (or a plain file
// standing in for one). Errors are Status values naming the path.
//
// Thread safety: one thread (the daemon's) drives a sink.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "relight/base/status.h"

namespace relight::daemon {

class FrameSink {
 public:
  virtual ~FrameSink() = default;
  // frame: 0, 1, 2, ... in the order written.
  virtual Status Write(const uint8_t* rgb, int width, int height, int64_t frame) = 0;
  // Called once after the last frame (a contact sheet is written here).
  virtual Status Finish() { return Status::Ok(); }
  virtual std::string Describe() const = 0;
};

// PNG files named by a printf pattern with one %d (frame number), e.g.
// "out/frames/f_%04d.png". kInvalidArgument for a pattern without one %d.
Status MakePngSequenceSink(const std::string& pattern, std::unique_ptr<FrameSink>* out);

// A stream of frames on stdout ("-") or a path (a FIFO, opened for writing
// at start-up, which blocks until a reader opens it). PPM: each frame a
// complete binary PPM ("P6 W H 255" + RGB); raw: only the RGB bytes.
// Readers: ffplay -f image2pipe -c:v ppm -i PATH, or a program of your own.
Status MakeStreamSink(const std::string& path, bool raw, std::unique_ptr<FrameSink>* out);

// A Linux framebuffer: geometry and pixel layout from the device's ioctls
// (FBIOGET_VSCREENINFO / FBIOGET_FSCREENINFO). A regular file (tests, or a
// frame dump) is written as `file_width` x `file_height` 32-bit XRGB8888
// little-endian. The frame goes at the top-left, clipped to the screen.
Status MakeFramebufferSink(const std::string& path, int file_width, int file_height, std::unique_ptr<FrameSink>* out);

// All frames, half size, tiled 4 per row into one PNG written by Finish().
// Keeps every tile in memory: for finite runs (--frames, --exit-when-replay-done).
Status MakeContactSheetSink(const std::string& path, std::unique_ptr<FrameSink>* out);

}  // namespace relight::daemon
