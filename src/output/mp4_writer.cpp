#include "output/mp4_writer.h"

#include <unistd.h>

#include <cstdio>
#include <stdexcept>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/imgutils.h>
#include <libavutil/opt.h>
#include <libyuv/convert.h>
}

namespace capflow::output {
namespace {
std::string av_err(int e) {
  char buf[AV_ERROR_MAX_STRING_SIZE] = {0};
  av_strerror(e, buf, sizeof buf);
  return buf;
}
void check(int e, const char* what) {
  if (e < 0) throw std::runtime_error(std::string("mp4: ") + what + ": " + av_err(e));
}
}  // namespace

struct Mp4Writer::Impl {
  Mp4Options opt;
  std::string path;
  AVFormatContext* fmt = nullptr;
  AVCodecContext* enc = nullptr;
  AVStream* st = nullptr;
  AVFrame* frame = nullptr;
  AVPacket* pkt = nullptr;
  bool open = false;
  int since_flush = 0;
  int64_t whole = 0;   // bytes of the file that end with a whole fragment (or the header)
  long in_file = 0;    // frames in those bytes
  bool failed = false;

  void drain(bool final_) {
    for (;;) {
      int r = avcodec_receive_packet(enc, pkt);
      if (r == AVERROR(EAGAIN) || r == AVERROR_EOF) return;
      check(r, "avcodec_receive_packet");
      pkt->duration = 1;  // codec time base (1/fps)
      av_packet_rescale_ts(pkt, enc->time_base, st->time_base);
      pkt->stream_index = st->index;
      check(av_write_frame(fmt, pkt), "av_write_frame");
      av_packet_unref(pkt);
      (void)final_;
    }
  }
  // Everything written so far reached the file (no error recorded by the I/O context): it ends
  // with a whole fragment now.
  void mark_whole(long frames) {
    if (!fmt || !fmt->pb) return;
    if (fmt->pb->error < 0) check(fmt->pb->error, ("write " + path).c_str());
    whole = avio_tell(fmt->pb);
    in_file = frames;
  }
  // After a failed write: the file cut back to its last whole fragment (a movie that holds no
  // frame at all is removed), so that it stays playable.
  void cut_back() {
    failed = true;
    release();
    if (in_file == 0)
      std::remove(path.c_str());
    else
      (void)::truncate(path.c_str(), whole);
  }
  void release() {
    av_frame_free(&frame);
    av_packet_free(&pkt);
    avcodec_free_context(&enc);
    if (fmt) {
      if (fmt->pb) avio_closep(&fmt->pb);
      avformat_free_context(fmt);
      fmt = nullptr;
    }
  }
};

Mp4Writer::Mp4Writer(const std::string& path, const Mp4Options& o) : impl_(new Impl) {
  if (o.width <= 0 || o.height <= 0 || o.width % 2 || o.height % 2)
    throw std::invalid_argument("mp4: width and height must be positive and even");
  if (o.fps < 1 || o.crf < 0 || o.crf > 51 || o.flush_every < 1 || o.threads < 0)
    throw std::invalid_argument(
        "mp4: need fps >= 1, crf in [0,51], flush_every >= 1, threads >= 0");
  // libx264 prints its statistics at info level on every close; keep the run log readable.
  if (av_log_get_level() > AV_LOG_WARNING) av_log_set_level(AV_LOG_WARNING);
  Impl& m = *impl_;
  m.opt = o;
  m.path = path;
  try {
    check(avformat_alloc_output_context2(&m.fmt, nullptr, "mp4", path.c_str()), "output context");
    const AVCodec* codec = avcodec_find_encoder_by_name("libx264");
    if (!codec) throw std::runtime_error("mp4: libx264 encoder not available in libavcodec");
    m.enc = avcodec_alloc_context3(codec);
    m.enc->width = o.width;
    m.enc->height = o.height;
    m.enc->time_base = AVRational{1, o.fps};
    m.enc->framerate = AVRational{o.fps, 1};
    m.enc->pix_fmt = AV_PIX_FMT_YUV420P;
    m.enc->gop_size = o.fps;
    m.enc->max_b_frames = 0;
    m.enc->thread_count = o.threads;
    if (m.fmt->oformat->flags & AVFMT_GLOBALHEADER) m.enc->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
    av_opt_set(m.enc->priv_data, "preset", o.preset.c_str(), 0);
    av_opt_set(m.enc->priv_data, "tune", "zerolatency", 0);
    av_opt_set(m.enc->priv_data, "crf", std::to_string(o.crf).c_str(), 0);
    check(avcodec_open2(m.enc, codec, nullptr), "open libx264");
    m.st = avformat_new_stream(m.fmt, nullptr);
    if (!m.st) throw std::runtime_error("mp4: cannot add stream");
    m.st->time_base = m.enc->time_base;
    check(avcodec_parameters_from_context(m.st->codecpar, m.enc), "codec parameters");
    check(avio_open(&m.fmt->pb, path.c_str(), AVIO_FLAG_WRITE), ("open " + path).c_str());
    AVDictionary* mux = nullptr;
    av_dict_set(&mux, "movflags", "frag_custom+empty_moov+default_base_moof", 0);
    const int r = avformat_write_header(m.fmt, &mux);
    av_dict_free(&mux);
    check(r, "write header");
    avio_flush(m.fmt->pb);
    m.mark_whole(0);
    m.frame = av_frame_alloc();
    m.frame->format = AV_PIX_FMT_YUV420P;
    m.frame->width = o.width;
    m.frame->height = o.height;
    check(av_frame_get_buffer(m.frame, 0), "frame buffer");
    m.pkt = av_packet_alloc();
    m.open = true;
  } catch (...) {
    m.cut_back();  // a movie that could not start is removed
    throw;
  }
}

Mp4Writer::~Mp4Writer() {
  try {
    finish();
  } catch (...) {
  }
}

void Mp4Writer::add_frame(const uint8_t* rgba, int stride) {
  Impl& m = *impl_;
  if (!m.open) throw std::logic_error("mp4: add_frame after finish");
  check(av_frame_make_writable(m.frame), "frame writable");
  // RGBA -> yuv420p (BT.601, limited range; chroma averaged over 2x2 pixels): libyuv names the
  // byte order R, G, B, A "ABGR" (the little-endian word). swscale took 3 ms a 1280x720 frame
  // on this path (no unscaled converter for RGBA); libyuv 0.3 ms (docs/performance.md, "x264").
  if (libyuv::ABGRToI420(rgba, stride ? stride : m.opt.width * 4, m.frame->data[0],
                         m.frame->linesize[0], m.frame->data[1], m.frame->linesize[1],
                         m.frame->data[2], m.frame->linesize[2], m.opt.width, m.opt.height) != 0)
    throw std::runtime_error("mp4: RGBA -> yuv420p conversion failed");
  m.frame->pts = frames_;
  try {
    check(avcodec_send_frame(m.enc, m.frame), "avcodec_send_frame");
    m.drain(false);
  } catch (...) {
    m.open = false;
    m.cut_back();
    throw;
  }
  ++frames_;
  if (++m.since_flush >= m.opt.flush_every) flush();
}

void Mp4Writer::flush() {
  Impl& m = *impl_;
  if (!m.open || m.since_flush == 0) return;
  try {
    check(av_write_frame(m.fmt, nullptr), "flush fragment");  // frag_custom: cut a fragment
    avio_flush(m.fmt->pb);
    m.mark_whole(frames_);
  } catch (...) {
    m.open = false;
    m.cut_back();
    throw;
  }
  m.since_flush = 0;
}

void Mp4Writer::finish() {
  Impl& m = *impl_;
  if (!m.open) return;
  m.open = false;
  try {
    check(avcodec_send_frame(m.enc, nullptr), "flush encoder");
    m.drain(true);
    check(av_write_trailer(m.fmt), "write trailer");
    avio_flush(m.fmt->pb);
    m.mark_whole(frames_);
  } catch (...) {
    m.cut_back();
    throw;
  }
  m.release();
  if (frames_ == 0) std::remove(m.path.c_str());  // a movie without a frame is no movie
}

long Mp4Writer::frames_in_file() const {
  return impl_->in_file;
}

}  // namespace capflow::output
