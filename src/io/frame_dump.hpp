#pragma once
// Frames of a run (`--dump_interval`): every body's position and velocity at regular steps, to
// watch a pull (or a pour) in ParaView or OVITO. They end up in the output file as H5MD time
// series under /particles/frames: position/{step,time,value} and velocity/{...} with value
// [frames x N x 3], species/value and radius/value [N] (fixed during a run), and a temporal XDMF
// sidecar `<output>.xdmf` that ParaView plays as an animation.
//
// While the run goes, frames are appended to a segment file `<output>.frames.<first frame>.h5`
// (written as .tmp and renamed when sealed). A checkpoint seals the open segment first, so every
// frame a checkpoint counts is in a complete file; a resumed run removes the segments written
// after its checkpoint and writes those frames again, bitwise the same as the state is. The
// output file copies the segments when the run ends; then they are removed.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "core/particles.hpp"
#include "io/h5_file.hpp"

namespace granudrag {

// Bytes one frame takes per body before compression: position and velocity, 3 float64 each.
constexpr std::size_t kFrameBytesPerParticle = 48;

class FrameDump {
 public:
  // `frames_kept`: the frames the checkpoint being resumed counts; 0 for a fresh run, which
  // removes segments an earlier run of this output left. Throws Error, naming the file, when
  // the sealed segments do not hold exactly frames 0 .. frames_kept-1 of `particles.size()` bodies.
  FrameDump(std::string output, const Particles& particles, long frames_kept);
  FrameDump(const FrameDump&) = delete;
  FrameDump& operator=(const FrameDump&) = delete;

  // Appends the frame of `p` at `step` (time `time`) to the open segment.
  void add(long step, double time, const Particles& p);
  // Seals the open segment (call before saving a checkpoint); nothing to do when none is open.
  void seal();
  long frames() const { return frames_; }

  // Seals the open segment and copies every frame into `out` under /particles/frames.
  void write_into(h5::File& out);
  // Removes the segment files (once the output that holds their frames is committed).
  void remove_segments();

  // The sealed segments of `output` on disk, in frame order: path and first frame.
  struct Segment {
    std::string path;
    long first = 0;
  };
  static std::vector<Segment> segments_of(const std::string& output);

 private:
  std::string segment_path(long first) const;

  std::string output_;
  std::size_t n_ = 0;
  std::vector<std::uint8_t> species_;
  std::vector<double> radius_;
  long frames_ = 0;
  // The open segment: its file, its two series, its first frame.
  std::optional<h5::File> open_;
  std::optional<h5::Series> position_, velocity_;
  long open_first_ = 0;
  std::vector<double> row_;
};

// The times of the frames in the bed or run file at `path` (none without frames).
std::vector<double> frame_times(const std::string& path);

}  // namespace granudrag
