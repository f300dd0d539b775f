// toolpoint: the gnuplot process — a script in, a picture renamed over the target (plot.hpp).
#include "toolpoint/plot/plot.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <poll.h>
#include <pthread.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>

#include "toolpoint/io/io.hpp"
#include "plot_detail.hpp"
#include "text.hpp"

extern char** environ;

namespace toolpoint::plot {

using namespace detail;
namespace fs = std::filesystem;

// ---- Running gnuplot -------------------------------------------------------------------------

void PlotOptions::check() const {
  require(!gnuplot.empty(), "PlotOptions::gnuplot is empty", "give the gnuplot program, e.g. \"gnuplot\"");
  check_fields(plot_fields(), *this, "PlotOptions");
}

const std::vector<OptionField<PlotOptions>>& plot_fields() {
  using O = PlotOptions;
  static const std::vector<OptionField<O>> fields = {{{.name = "timeout_s",
                                                       .kind = FieldKind::Real,
                                                       .unit = "s",
                                                       .min = 0.0,
                                                       .min_open = true,
                                                       .help = "gnuplot is killed after this many seconds"},
                                                      [](O& o) -> double& { return o.timeout_s; }}};
  return fields;
}

namespace {

// While a pipe to a child is written, SIGPIPE is blocked in this thread (so a child that exits
// early gives EPIPE, not the death of the caller) and a SIGPIPE raised meanwhile is consumed.
class SigpipeBlock {
 public:
  SigpipeBlock() {
    sigemptyset(&pipe_);
    sigaddset(&pipe_, SIGPIPE);
    pthread_sigmask(SIG_BLOCK, &pipe_, &old_);
    sigset_t pending;
    sigpending(&pending);
    was_pending_ = sigismember(&pending, SIGPIPE) == 1;
  }
  ~SigpipeBlock() {
    sigset_t pending;
    sigpending(&pending);
    if (!was_pending_ && sigismember(&pending, SIGPIPE) == 1) {
      const timespec zero{0, 0};
      sigtimedwait(&pipe_, nullptr, &zero);
    }
    pthread_sigmask(SIG_SETMASK, &old_, nullptr);
  }
  SigpipeBlock(const SigpipeBlock&) = delete;
  SigpipeBlock& operator=(const SigpipeBlock&) = delete;

 private:
  sigset_t pipe_{}, old_{};
  bool was_pending_ = false;
};

class Fd {
 public:
  explicit Fd(int fd = -1) : fd_(fd) {}
  ~Fd() { reset(); }
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  int get() const { return fd_; }
  void reset() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }

 private:
  int fd_;
};

struct ChildOutcome {
  int status = 0;
  std::string err;
};

// Runs `program -d -` (no init files, script on stdin), feeding `script` and collecting stderr
// concurrently so that neither pipe can fill up and stall the other.
ChildOutcome run_gnuplot(const PlotOptions& o, const std::string& script) {
  int in[2], err[2];
  if (::pipe2(in, O_CLOEXEC) != 0) throw IoError(fmt::format("cannot create a pipe to gnuplot ({})", std::strerror(errno)));
  Fd in_read(in[0]), in_write(in[1]);
  if (::pipe2(err, O_CLOEXEC) != 0) throw IoError(fmt::format("cannot create a pipe from gnuplot ({})", std::strerror(errno)));
  Fd err_read(err[0]), err_write(err[1]);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, in_read.get(), 0);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, err_write.get(), 2);
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  sigset_t none, pipe_default;
  sigemptyset(&none);
  sigemptyset(&pipe_default);
  sigaddset(&pipe_default, SIGPIPE);
  posix_spawnattr_setsigmask(&attr, &none);
  posix_spawnattr_setsigdefault(&attr, &pipe_default);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
  std::string arg0 = o.gnuplot, arg1 = "-d", arg2 = "-";
  char* argv[] = {arg0.data(), arg1.data(), arg2.data(), nullptr};
  pid_t pid = -1;
  const int rc = ::posix_spawnp(&pid, o.gnuplot.c_str(), &actions, &attr, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attr);
  if (rc != 0)
    throw PlotUnavailable(fmt::format("gnuplot not found: cannot run '{}' ({})", o.gnuplot, std::strerror(rc)),
                          "install gnuplot (Debian: apt-get install gnuplot-nox) and make sure it is on PATH");
  in_read.reset();
  err_write.reset();

  ChildOutcome out;
  SigpipeBlock no_sigpipe;
  ::fcntl(in_write.get(), F_SETFL, ::fcntl(in_write.get(), F_GETFL) | O_NONBLOCK);
  std::size_t written = 0;
  if (script.empty()) in_write.reset();
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(o.timeout_s);
  constexpr std::size_t kMaxErr = 1 << 20;  // a runaway stream of warnings is cut, not buffered whole
  bool err_open = true;
  while (err_open) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, nullptr, 0);
      throw IoError(fmt::format("gnuplot ('{}') did not finish within {} s and was stopped", o.gnuplot, o.timeout_s),
                    "simplify the figure (fewer points) or raise PlotOptions::timeout_s");
    }
    pollfd fds[2] = {{err_read.get(), POLLIN, 0}, {in_write.get(), POLLOUT, 0}};
    const nfds_t n = in_write.get() >= 0 ? 2 : 1;
    if (::poll(fds, n, static_cast<int>(std::min<long long>(left.count(), 1000))) < 0) {
      if (errno == EINTR) continue;
      const std::string why = std::strerror(errno);
      ::kill(pid, SIGKILL);
      ::waitpid(pid, nullptr, 0);
      throw IoError(fmt::format("lost contact with gnuplot ('{}'): poll failed ({})", o.gnuplot, why));
    }
    if (fds[0].revents != 0) {
      char buf[4096];
      const ssize_t got = ::read(err_read.get(), buf, sizeof buf);
      if (got > 0) {
        if (out.err.size() < kMaxErr) out.err.append(buf, static_cast<std::size_t>(got));
      } else if (got == 0 || errno != EINTR) {
        err_open = false;
      }
    }
    if (n == 2 && fds[1].revents != 0) {
      const ssize_t put = ::write(in_write.get(), script.data() + written, script.size() - written);
      if (put > 0) written += static_cast<std::size_t>(put);
      if ((put < 0 && errno != EAGAIN && errno != EINTR) || written == script.size()) in_write.reset();
    }
  }
  in_write.reset();
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {}
  out.status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
  return out;
}

// The terminal, chosen inside gnuplot from what this gnuplot was built with; the choice is
// reported back on stderr through "toolpoint-…:" lines. PDF keeps the PNG's proportions: the
// cairo PNG works at 72 px per inch, and pdfcairo's default font and line scale is one half.
std::string terminal_lines(Format format, int w, int h) {
  const std::string font = fmt::format("font \"{},{}\"", kFont, kFontPt);
  switch (format) {
    case Format::Png:
      return fmt::format(
          "if (strstrt(GPVAL_TERMINALS, \" pngcairo \") > 0) {{\n"
          "  set terminal pngcairo size {0},{1} enhanced {2} linewidth 1 rounded background \"#FFFFFF\"\n"
          "  print \"toolpoint-terminal: pngcairo\"\n"
          "}} else {{\n"
          "  set terminal png size {0},{1} enhanced truecolor font \"DejaVuSans,{3}\"\n"
          "  print \"toolpoint-terminal: png\"\n"
          "  print \"toolpoint-note: gnuplot has no pngcairo terminal; used the libgd png terminal (no anti-aliasing, "
          "plainer dashes)\"\n"
          "}}\n",
          w, h, font, kFontPt - 4);
    case Format::Svg:
      return fmt::format(
          "set terminal svg size {},{} enhanced {} linewidth 1 rounded background \"#FFFFFF\"\n"
          "print \"toolpoint-terminal: svg\"\n",
          w, h, font);
    case Format::Pdf:
      return fmt::format(
          "if (strstrt(GPVAL_TERMINALS, \" pdfcairo \") == 0) {{\n"
          "  print \"toolpoint-unavailable: gnuplot has no pdfcairo terminal, so it cannot write PDF\"\n"
          "  exit status 3\n"
          "}}\n"
          "set terminal pdfcairo size {:.6f},{:.6f} enhanced {} fontscale 1 linewidth 2 rounded background \"#FFFFFF\"\n"
          "print \"toolpoint-terminal: pdfcairo\"\n",
          (w + 0.01) / 72.0, (h + 0.01) / 72.0, font);  // a hair over, or cairo truncates to a point less
  }
  return {};
}

}  // namespace

RenderResult render_script(const std::string& body, const std::string& path, int width_px, int height_px,
                           const PlotOptions& options) {
  options.check();
  const Format format = format_for_path(path);
  check_size(width_px, height_px);
  AtomicOutput tmp(path);
  const std::string script = terminal_lines(format, width_px, height_px) + "set output " + gp_path(tmp.path()) + "\n" + body +
                             "\nunset output\n";
  const ChildOutcome run = run_gnuplot(options, script);

  RenderResult result;
  result.path = path;
  result.format = format;
  std::string unavailable;
  std::vector<std::string> said;  // gnuplot's own lines (not toolpoint-tagged)
  std::size_t start = 0;
  while (start < run.err.size()) {
    std::size_t end = run.err.find('\n', start);
    if (end == std::string::npos) end = run.err.size();
    const std::string line = run.err.substr(start, end - start);
    start = end + 1;
    auto tagged = [&](std::string_view tag) {
      return line.rfind(tag, 0) == 0 ? std::string(text::trim(std::string_view(line).substr(tag.size()))) : std::string();
    };
    if (auto t = tagged("toolpoint-terminal:"); !t.empty()) {
      result.terminal = t;
    } else if (auto n = tagged("toolpoint-note:"); !n.empty()) {
      result.notes.push_back(n);
    } else if (auto u = tagged("toolpoint-unavailable:"); !u.empty()) {
      unavailable = u;
    } else {
      said.push_back(line);
    }
  }
  // What gnuplot said, without blank lines or blanks around it.
  while (!said.empty() && text::is_blank(said.back())) said.pop_back();
  std::size_t first = 0;
  while (first < said.size() && text::is_blank(said[first])) ++first;
  std::string message;
  for (std::size_t i = first; i < said.size(); ++i) message += (i > first ? "\n" : "") + said[i];
  message = std::string(text::trim(message));
  if (!unavailable.empty())
    throw PlotUnavailable(fmt::format("{}: {} ('{}')", path, unavailable, options.gnuplot),
                          "install a gnuplot built with cairo (Debian: gnuplot-nox) or write .png/.svg instead");
  if (run.status != 0) {
    if (message.size() > 4000) message = "…" + message.substr(message.size() - 4000);
    throw IoError(fmt::format("{}: gnuplot failed (exit status {}); nothing was written. gnuplot said:\n{}", path, run.status,
                              message.empty() ? "(nothing)" : message),
                  "the message above names the gnuplot command at fault");
  }
  std::error_code ec;
  const auto size = fs::file_size(tmp.path(), ec);
  if (ec || size == 0) throw IoError(fmt::format("{}: gnuplot reported success but wrote nothing; nothing was written", path));
  for (const std::string& line : said)
    if (const std::string_view w = text::trim(line); !w.empty()) result.warnings.emplace_back(w);
  tmp.commit();
  return result;
}

RenderResult render(const Figure& figure, const std::string& path, const PlotOptions& options) {
  format_for_path(path);  // a bad extension is reported before any work
  return render_script(gnuplot_script(figure), path, figure.width_px, figure.height_px, options);
}

}  // namespace toolpoint::plot
