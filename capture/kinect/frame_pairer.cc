#include "capture/kinect/frame_pairer.h"

#include "core/check.h"

namespace mocap::capture {

FramePairer::FramePairer(int64_t tolerance_ticks) : tolerance_ticks_(tolerance_ticks) {
  MOCAP_CHECK(tolerance_ticks >= 0, "negative pairing tolerance ", tolerance_ticks);
}

std::optional<ImagePair> FramePairer::AddDepth(StampedImage depth) { return Add(kDepth, std::move(depth)); }
std::optional<ImagePair> FramePairer::AddColor(StampedImage color) { return Add(kColor, std::move(color)); }

std::optional<ImagePair> FramePairer::Add(Stream stream, StampedImage image) {
  const Stream other = stream == kDepth ? kColor : kDepth;
  std::optional<StampedImage>& partner = waiting_[other];
  if (partner) {
    const int64_t dt = image.ticks - partner->ticks;
    if (dt >= -tolerance_ticks_ && dt <= tolerance_ticks_) {
      ImagePair pair = stream == kDepth ? ImagePair{std::move(image), std::move(*partner)}
                                        : ImagePair{std::move(*partner), std::move(image)};
      partner.reset();
      return pair;
    }
    if (dt > tolerance_ticks_) {
      // The partner is too old for this image and for every later one of this stream.
      ++unpaired_[other];
      partner.reset();
    } else {
      // The partner is newer than this image by more than the tolerance: this one can never pair.
      ++unpaired_[stream];
      return std::nullopt;
    }
  }
  if (waiting_[stream]) ++unpaired_[stream];
  waiting_[stream] = std::move(image);
  return std::nullopt;
}

}  // namespace mocap::capture
