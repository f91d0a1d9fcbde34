// monocle record: the running service's topics into an MCAP file; monocle info: what a
// recording holds, from its index (or recovered from a file cut short).
#include <unistd.h>

#include <cmath>
#include <csignal>
#include <cstdlib>
#include <ctime>
#include <iomanip>
#include <iostream>
#include <optional>
#include <set>
#include <sstream>

#include "client/cli/args.h"
#include "client/cli/command_line.h"
#include "client/cli/commands.h"
#include "client/cli/live.h"
#include "client/cli/shared_options.h"
#include "idl/record/recorder.h"
#include "service/io/mcap_reader.h"

namespace monocle::cli {
namespace {

constexpr const char* kRecordAbout =
    R"(Records what the running service publishes into an MCAP file (ROS 2's bag format; Foxglove
and `ros2 bag` open it): per camera its corner poses, poses, camera info, frames and the
requests and replies of its services, and for all cameras their status, calibrations, /tf,
/tf_static and /diagnostics. Messages are stored as they travelled (CDR) with their ROS 2
message definitions. Runs until Ctrl-C, SIGTERM or --duration; the file is then closed with
its index. A file cut short (power loss, SIGKILL) keeps every complete chunk: `monocle info`
recovers it.)";

constexpr const char* kRecordFooter =
    R"(On a terminal it shows messages and bytes per topic as it records; otherwise it is quiet.
Exit status 1 if the recording stopped early (e.g. the disk is full; the file stays readable).)";

std::string Megabytes(uint64_t bytes) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(1) << bytes / 1e6 << " MB";
  return s.str();
}

std::string UtcTime(uint64_t ns) {
  const std::time_t t = static_cast<std::time_t>(ns / 1000000000ull);
  std::tm tm{};
  gmtime_r(&t, &tm);
  std::ostringstream s;
  s << std::put_time(&tm, "%Y-%m-%d %H:%M:%S") << '.' << std::setw(3) << std::setfill('0')
    << (ns / 1000000ull) % 1000 << " UTC";
  return s.str();
}

// The progress block on a terminal: rewritten in place.
class Progress {
 public:
  void Show(double elapsed_s, const record::Recorder& recorder) {
    std::ostringstream out;
    if (lines_ > 0) out << "\033[" << lines_ << "A";  // back to the block's first line
    int lines = 0;
    out << "\033[2Krecording " << std::fixed << std::setprecision(1) << elapsed_s << " s, "
        << Megabytes(recorder.file_bytes()) << " written  (Ctrl-C to stop)\n";
    ++lines;
    for (const record::TopicStats& t : recorder.stats()) {
      if (t.messages == 0) continue;
      out << "\033[2K  " << std::left << std::setw(44) << t.topic << std::right << std::setw(9)
          << t.messages << " msgs " << std::setw(10) << Megabytes(t.bytes) << "\n";
      ++lines;
    }
    // Lines from an earlier, longer block (never: topics only appear) are left as they are.
    lines_ = lines;
    std::cerr << out.str() << std::flush;
  }

 private:
  int lines_ = 0;
};

// --frames none|every|N: record no frames, every frame or every Nth; false for anything else.
bool ParseFramesEvery(const std::string& frames, int* frames_every) {
  if (frames == "none") {
    *frames_every = 0;
  } else if (frames == "every") {
    *frames_every = 1;
  } else if (auto n = ParseDouble(frames); n && *n >= 1 && *n <= 1e6 && *n == std::floor(*n)) {
    *frames_every = static_cast<int>(*n);
  } else {
    return false;
  }
  return true;
}

// The namespaces of the cameras asked for by id or namespace; kExitOk, or the exit status of
// a camera that is not there (its message names the cameras that are).
int NamespacesOf(const std::vector<std::string>& wanted, const std::vector<CameraStatus>& cameras,
                 std::set<std::string>* namespaces) {
  for (const std::string& id : wanted) {
    bool found = false;
    for (const CameraStatus& c : cameras) {
      if (c.camera_id == id || c.ros_namespace == id) {
        namespaces->insert(c.ros_namespace);
        found = true;
      }
    }
    if (!found) {
      std::string known;
      for (const CameraStatus& c : cameras) known += (known.empty() ? "" : ", ") + c.camera_id;
      return Fail("no camera '" + id +
                      "' on the domain (cameras: " + (known.empty() ? "none" : known) + ")",
                  kExitFailure);
    }
  }
  return kExitOk;
}

struct RecordArgs {
  std::string out;
  std::vector<std::string> cameras;
  record::RecordOptions options;
  double duration_s = 0;
  LiveOptions live;
};

void DeclareRecord(CommandLine& line, RecordArgs* a) {
  line.Footer(kRecordFooter);
  line.Text("--out", &a->out, "FILE.mcap", "the recording (overwritten)");
  line.Require("--out");
  line.Texts("--camera", &a->cameras, "ID",
             "a camera to record (default every camera on the "
             "domain)");
  line.Custom("--frames", "none|every|N",
              "none (default), every frame, or every Nth frame the service sends. The service "
              "sends frames at most at its camera's image_max_rate_hz (configuration, default "
              "5 Hz); raise it to record every frame",
              [a](const std::string& text) -> std::optional<std::string> {
                if (ParseFramesEvery(text, &a->options.frames_every)) return std::nullopt;
                return "must be none, every, or a whole number N >= 1 (every Nth frame)";
              });
  line.Number("--duration", &a->duration_s, "S", "stop after S seconds (0: until Ctrl-C)",
              In("seconds").AtLeast(0));
  line.Flag("--zstd", &a->options.zstd, "compress the file losslessly (zstd chunks)");
  DeclareServiceOptions(line, &a->live, "wait up to S seconds for the service's cameras");
}

// Records until `duration_s` (0: no limit), a stop signal in `stop` or the recorder's error;
// `progress`, when given, is shown as it goes.
void RecordUntilStopped(const record::Recorder& recorder, double duration_s, const sigset_t& stop,
                        Progress* progress) {
  const auto start = std::chrono::steady_clock::now();
  while (true) {
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (progress) progress->Show(elapsed, recorder);
    if ((duration_s > 0 && elapsed >= duration_s) || recorder.error()) break;
    double wait_s = 0.5;
    if (duration_s > 0) wait_s = std::min(wait_s, duration_s - elapsed);
    const timespec wait{static_cast<time_t>(wait_s),
                        static_cast<long>((wait_s - std::floor(wait_s)) * 1e9)};
    if (sigtimedwait(&stop, nullptr, &wait) > 0) break;
  }
}

// Per recorded camera, how many of the frames it took while recording were recorded, and why
// fewer (`before`: the cameras' status when the recording began).
void ReportFrames(Client& client, const std::vector<CameraStatus>& before,
                  const std::set<std::string>& namespaces, int frames_every,
                  const record::Recorder& recorder) {
  const auto after = client.status();
  if (!after) return;
  for (const CameraStatus& b : before) {
    if (!namespaces.count(b.ros_namespace)) continue;
    uint64_t recorded = 0;
    for (const record::TopicStats& t : recorder.stats())
      if (t.topic == b.ros_namespace + "/image_raw") recorded = t.messages;
    for (const CameraStatus& a : *after) {
      if (a.camera_id != b.camera_id || a.frames < b.frames) continue;
      const uint64_t taken = a.frames - b.frames, asked = taken / frames_every;
      std::cerr << "monocle: " << b.camera_id << ": " << recorded << " of its " << taken
                << " frames recorded";
      if (recorded + 1 < asked) {
        std::cerr << " (" << asked << " asked; the service sent no more: its "
                  << "image_max_rate_hz caps them)";
      }
      std::cerr << "\n";
    }
  }
}

}  // namespace

int RecordCommand(const std::vector<std::string>& argv) {
  RecordArgs a;
  CommandLine line("record", kRecordAbout);
  DeclareRecord(line, &a);
  if (const auto exit_now = line.Parse(argv)) return *exit_now;
  record::RecordOptions& options = a.options;
  const std::string* out = &a.out;
  const double* duration_s = &a.duration_s;

  // Ctrl-C and SIGTERM end the recording cleanly: blocked before any thread starts, waited
  // for below. A file size limit (SIGXFSZ) must end the recording with its summary, not kill.
  sigset_t stop;
  sigemptyset(&stop);
  sigaddset(&stop, SIGINT);
  sigaddset(&stop, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop, nullptr);
  std::signal(SIGXFSZ, SIG_IGN);

  int exit_status = kExitOk;
  auto client = OpenClient(a.live, &exit_status);
  if (!client) return exit_status;
  const auto cameras = client->status();
  if (!cameras) return Fail(cameras.error());
  const std::vector<std::string>& wanted = a.cameras;
  std::set<std::string> namespaces;
  if (int status = NamespacesOf(wanted, *cameras, &namespaces); status != kExitOk) return status;
  if (wanted.empty()) {
    for (const CameraStatus& c : *cameras) namespaces.insert(c.ros_namespace);
  }
  options.namespaces.assign(namespaces.begin(), namespaces.end());

  const int domain = a.live.domain;
  std::string security = a.live.security_dir.value_or("");
  if (security.empty()) {
    if (const char* env = std::getenv("MONOCLE_SECURITY")) security = env;
  }
  auto participant = dds::CreateParticipant(domain, security);
  if (!participant) return Fail(participant.error(), kExitFailure);
  if (options.frames_every > 0) {
    std::cerr << "monocle: note: the service sends a camera's frames at most at its "
                 "image_max_rate_hz (configuration, default 5 Hz), so --frames records at most "
                 "that many a second; to record every frame, raise image_max_rate_hz or record "
                 "in monocled itself (monocled --record FILE.mcap --record-frames every)\n";
  }
  auto recorder = record::Recorder::Start(*participant, *out, options);
  if (!recorder) return Fail(recorder.error(), kExitFailure);
  for (const std::string& s : (*recorder)->skipped()) {
    std::cerr << "monocle: warning: not recorded: " << s << "\n";
  }

  const bool tty = ::isatty(STDERR_FILENO) == 1;
  Progress progress;
  const auto start = std::chrono::steady_clock::now();
  RecordUntilStopped(**recorder, *duration_s, stop, tty ? &progress : nullptr);
  const Status finished = (*recorder)->Finish();
  if (tty) {
    progress.Show(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                  **recorder);
  }
  if (!finished) {
    return Fail(finished.error().message + "; " + *out + " holds everything before it",
                kExitFailure);
  }
  if (options.frames_every > 0)
    ReportFrames(*client, *cameras, namespaces, options.frames_every, **recorder);
  if (tty) std::cerr << "recorded " << *out << "\n";
  return kExitOk;
}

namespace {

// A JSON string: quotes, backslashes and control characters escaped.
std::string Quoted(const std::string& text) {
  std::ostringstream out;
  out << '"';
  for (const char c : text) {
    if (c == '"' || c == '\\') {
      out << '\\' << c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      out << "\\u" << std::hex << std::setw(4) << std::setfill('0') << int{c} << std::dec;
    } else {
      out << c;
    }
  }
  out << '"';
  return out.str();
}

// What `info` says of one recording.
struct RecordingInfo {
  std::string path;
  const mcap::Summary* summary = nullptr;
  std::set<std::string> cameras;          // the namespaces of per-camera topics
  std::optional<mcap::ChunkCheck> check;  // --check

  uint64_t CountOf(uint16_t channel) const {
    const auto it = summary->channel_message_counts.find(channel);
    return it == summary->channel_message_counts.end() ? uint64_t{0} : it->second;
  }
  std::string SchemaOf(uint16_t schema) const {
    const auto it = summary->schemas.find(schema);
    return it == summary->schemas.end() ? "" : it->second.name;
  }
};

std::set<std::string> CamerasOf(const mcap::Summary& s) {
  std::set<std::string> cameras;
  for (const auto& [id, ch] : s.channels) {
    for (const std::string leaf : {"/corner_pose", "/camera_info"}) {
      if (ch.topic.size() > leaf.size() && ch.topic.ends_with(leaf))
        cameras.insert(ch.topic.substr(0, ch.topic.size() - leaf.size()));
    }
  }
  return cameras;
}

void PrintInfoJson(const RecordingInfo& info) {
  const mcap::Summary& s = *info.summary;
  std::ostringstream j;
  j << "{\"file\":" << Quoted(info.path) << ",\"bytes\":" << s.file_bytes
    << ",\"profile\":" << Quoted(s.profile) << ",\"library\":" << Quoted(s.library)
    << ",\"messages\":" << s.message_count << ",\"chunks\":" << s.chunk_count
    << ",\"start_ns\":" << s.start_time_ns << ",\"end_ns\":" << s.end_time_ns
    << ",\"from_index\":" << (s.from_index ? "true" : "false")
    << ",\"recovered\":" << (s.recovered ? "true" : "false") << ",\"cameras\":[";
  bool first = true;
  for (const std::string& c : info.cameras) {
    j << (first ? "" : ",") << Quoted(c);
    first = false;
  }
  j << "],\"topics\":[";
  first = true;
  for (const auto& [id, ch] : s.channels) {
    j << (first ? "" : ",") << "{\"topic\":" << Quoted(ch.topic)
      << ",\"type\":" << Quoted(info.SchemaOf(ch.schema_id)) << ",\"messages\":" << info.CountOf(id)
      << "}";
    first = false;
  }
  j << "]";
  if (info.check) {
    j << ",\"check\":{\"intact\":" << info.check->intact << ",\"damaged\":[";
    first = true;
    for (const mcap::DamagedChunk& d : info.check->damaged) {
      j << (first ? "" : ",") << "{\"offset\":" << d.offset << ",\"why\":" << Quoted(d.why) << "}";
      first = false;
    }
    j << "]}";
  }
  std::cout << j.str() << "}\n";
}

void PrintInfoText(const RecordingInfo& info) {
  const mcap::Summary& s = *info.summary;
  std::cout << "file:      " << info.path << " (" << Megabytes(s.file_bytes) << ", "
            << s.chunk_count << " chunks, written by " << s.library << ")\n";
  if (s.recovered) std::cout << "recovered: " << s.recovery_note << "\n";
  if (s.message_count > 0) {
    std::cout << "start:     " << UtcTime(s.start_time_ns)
              << "\nend:       " << UtcTime(s.end_time_ns) << "\nduration:  " << std::fixed
              << std::setprecision(3) << static_cast<double>(s.end_time_ns - s.start_time_ns) / 1e9
              << " s\n";
  }
  std::cout << "messages:  " << s.message_count << "\ncameras:  ";
  for (const std::string& c : info.cameras) std::cout << " " << c;
  std::cout << (info.cameras.empty() ? " none\n" : "\n") << "topics:\n";
  for (const auto& [id, ch] : s.channels) {
    std::cout << "  " << std::left << std::setw(44) << ch.topic << std::setw(46)
              << info.SchemaOf(ch.schema_id) << std::right << std::setw(8) << info.CountOf(id)
              << "\n";
  }
  if (!info.check) return;
  if (info.check->damaged.empty()) {
    std::cout << "check:     all " << info.check->intact << " chunks read, intact\n";
    return;
  }
  std::cout << "check:     " << info.check->damaged.size() << " damaged chunk(s), "
            << info.check->intact << " intact (replay skips the damaged ones):\n";
  for (const mcap::DamagedChunk& d : info.check->damaged)
    std::cout << "  at byte " << d.offset << ": " << d.why << "\n";
}

}  // namespace

int InfoCommand(const std::vector<std::string>& argv) {
  std::vector<std::string> file;
  bool json = false, check = false;
  CommandLine line("info",
                   "What a recording holds: its time span, cameras, and per topic the message type "
                   "and count. A\nclosed file is summarised from its index without reading the "
                   "messages; a file cut short\n(recorder killed, disk full) is scanned, and what "
                   "was kept is said.");
  line.Positionals("FILE.mcap", &file, "the recording", 1, 1);
  line.Flag("--check", &check,
            "read every chunk too (decompress, CRC, records) and name the damaged ones; exit "
            "status 1 if any is");
  line.Flag("--json", &json, "print one JSON object (with --check: check {intact, damaged[]})");
  if (const auto exit_now = line.Parse(argv)) return *exit_now;
  auto reader = mcap::Reader::Open(file[0]);
  if (!reader) return Fail(reader.error(), kExitFailure);
  RecordingInfo info{file[0], &reader->summary(), CamerasOf(reader->summary()), std::nullopt};
  if (check) {
    auto checked = reader->CheckChunks();
    if (!checked) return Fail(checked.error(), kExitFailure);
    info.check = std::move(checked).value();
  }
  if (json) {
    PrintInfoJson(info);
  } else {
    PrintInfoText(info);
  }
  return info.check && !info.check->damaged.empty() ? kExitFailure : kExitOk;
}

}  // namespace monocle::cli
