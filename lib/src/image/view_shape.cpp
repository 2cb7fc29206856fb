#include "image/view_shape.h"

namespace gdof::image_detail {

namespace {

std::string channels_text(int n) { return std::to_string(n) + (n == 1 ? " channel" : " channels"); }

}  // namespace

Status check_view_shape(const ConstImageView& view, int nchannels, const Roi& window, const std::string& what) {
    const bool channels_ok = nchannels == kAnyChannelCount ? view.nchannels >= 0 : view.nchannels == nchannels;
    if (view.valid() && channels_ok && view.window == window) return Status::ok();
    const std::string have = view.valid() ? channels_text(view.nchannels) + " over " + to_string(view.window)
                                          : "a view without pixels (null base) over " + to_string(view.window);
    const std::string want = (nchannels == kAnyChannelCount ? std::string("channels") : channels_text(nchannels)) +
                             " over " + to_string(window);
    return Status::error(what + " is " + have + "; expected " + want, StatusCode::InvalidArgument);
}

}  // namespace gdof::image_detail
