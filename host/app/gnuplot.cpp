#include "host/app/gnuplot.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <vector>

#include "host/error.h"
#include "host/image/image_io.h"

extern char** environ;

namespace caustica {
namespace {

namespace fs = std::filesystem;

constexpr const char* kInstallHint =
    "gnuplot is not installed; caustica draws plots and heatmaps with it: "
    "apt-get install gnuplot-nox (or run tools/setup.sh)";

// Anchors of matplotlib's viridis (perceptually uniform, readable in grey and
// by the common colour-vision deficiencies); gnuplot interpolates between them.
constexpr const char* kViridis =
    "set palette defined (0 '#440154', 1 '#472c7a', 2 '#3b518b', 3 '#2c718e', 4 '#21908d', "
    "5 '#27ad81', 6 '#5cc863', 7 '#aadc32', 8 '#fde725')\n";

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// gnuplot's messages can be long (a warning per plotted point); the last ones hold the error.
std::string last_chars(std::string text, size_t max_chars) {
  while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.pop_back();
  if (text.size() > max_chars) text = "..." + text.substr(text.size() - max_chars);
  return text;
}

}  // namespace

TempDir::TempDir() {
  std::string pattern = (fs::temp_directory_path() / "caustica-XXXXXX").string();
  std::vector<char> buf(pattern.begin(), pattern.end());
  buf.push_back('\0');
  if (!mkdtemp(buf.data()))
    throw Error("cannot create a temporary directory like '" + pattern + "': " + std::strerror(errno));
  path_ = buf.data();
}

TempDir::~TempDir() {
  std::error_code ec;
  fs::remove_all(path_, ec);  // best effort: a destructor must not throw
}

bool gnuplot_available() {
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "/usr/bin:/bin";
  size_t start = 0;
  while (start <= dirs.size()) {
    const size_t end = std::min(dirs.find(':', start), dirs.size());
    const std::string dir = end > start ? dirs.substr(start, end - start) : ".";
    if (::access((dir + "/gnuplot").c_str(), X_OK) == 0) return true;
    start = end + 1;
  }
  return false;
}

std::string gnuplot_quote(const std::string& text) {
  std::string out = "'";
  for (char c : text) {
    if (c == '\n' || c == '\r') throw Error("cannot pass a text with a line break to gnuplot: '" + text + "'");
    out += c;
    if (c == '\'') out += '\'';
  }
  return out + "'";
}

std::string gnuplot_output(const std::string& out_path, int width, int height) {
  const std::string ext = lower_extension(out_path);
  const std::string size = " size " + std::to_string(width) + "," + std::to_string(height);
  std::string terminal;
  if (ext == ".png") terminal = "set terminal pngcairo enhanced font 'sans,10'" + size;
  else if (ext == ".svg") terminal = "set terminal svg enhanced font 'sans,10' background '#ffffff'" + size;
  else throw Error("cannot draw '" + out_path + "': unknown extension '" + ext + "' (supported: .png, .svg)");
  return terminal + "\nset output " + gnuplot_quote(out_path) + "\n";
}

void draw_heatmap(const std::vector<float>& values, int width, int height, const ColourBar& bar,
                  const std::string& title, const std::string& out_path) {
  TempDir dir;
  const std::string data_path = dir.path() + "/values.f32";
  {
    std::ofstream out(data_path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(values.data()), static_cast<std::streamsize>(values.size() * 4));
    if (!out.flush()) throw Error("cannot draw '" + out_path + "': cannot write '" + data_path + "'");
  }

  const int w = width, h = height;
  const int scale = std::max(1, static_cast<int>(std::ceil(400.0 / std::max(w, h))));
  const int left = 16, right = 130, bottom = 16, top = title.empty() ? 16 : 40;
  const int draw_w = w * scale, draw_h = h * scale;
  const int canvas_w = left + draw_w + right, canvas_h = bottom + draw_h + top;
  auto x_at = [&](int px) { return std::to_string(double(px) / canvas_w); };
  auto y_at = [&](int px) { return std::to_string(double(px) / canvas_h); };
  char cb[160];

  std::ostringstream gp;
  gp << gnuplot_output(out_path, canvas_w, canvas_h);
  gp << "set lmargin at screen " << x_at(left) << "\nset rmargin at screen " << x_at(left + draw_w)
     << "\nset bmargin at screen " << y_at(bottom) << "\nset tmargin at screen " << y_at(bottom + draw_h) << "\n";
  gp << "unset xtics\nunset ytics\nunset key\n";
  gp << "set xrange [-0.5:" << w - 0.5 << "]\nset yrange [-0.5:" << h - 0.5 << "]\n";
  if (bar.log_scale) gp << "set logscale cb\n";
  std::snprintf(cb, sizeof cb, "set cbrange [%.9g:%.9g]\n", bar.lo, bar.hi);
  gp << cb;
  if (!bar.tic_format.empty()) gp << "set format cb " << gnuplot_quote(bar.tic_format) << "\n";
  if (bar.tic_step > 0.0) {
    std::snprintf(cb, sizeof cb, "set cbtics %.9g\n", bar.tic_step);
    gp << cb;
  }
  gp << kViridis;
  gp << "set cblabel " << gnuplot_quote(bar.label) << " noenhanced offset " << bar.label_offset << ",0\n";
  gp << "set colorbox vertical user origin screen " << x_at(left + draw_w + 16) << ", screen " << y_at(bottom)
     << " size screen " << x_at(18) << ", screen " << y_at(draw_h) << "\n";
  if (!title.empty()) gp << "set title " << gnuplot_quote(title) << " noenhanced\n";
  // The file holds rows top first; flipy puts its first row at the top.
  gp << "plot " << gnuplot_quote(data_path) << " binary array=(" << w << "," << h
     << ") format='%float32' flipy with image notitle\n";
  run_gnuplot(gp.str(), out_path);
}

void run_gnuplot(const std::string& script, const std::string& out_path) {
  if (!gnuplot_available()) throw Error("cannot draw '" + out_path + "': " + kInstallHint);
  TempDir dir;
  const std::string script_path = dir.path() + "/plot.gp", log_path = dir.path() + "/gnuplot.log";
  {
    std::ofstream out(script_path, std::ios::binary);
    out << script;
    if (!out.flush()) throw Error("cannot write the gnuplot script '" + script_path + "'");
  }
  std::error_code ec;
  fs::remove(out_path, ec);  // so a stale file is never mistaken for this run's output

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  std::string prog = "gnuplot";
  std::vector<char*> argv = {prog.data(), const_cast<char*>(script_path.c_str()), nullptr};
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, "gnuplot", &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc == ENOENT) throw Error("cannot draw '" + out_path + "': " + kInstallHint);
  if (rc != 0) throw Error("cannot draw '" + out_path + "': starting gnuplot failed: " + std::strerror(rc));
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) throw Error("cannot draw '" + out_path + "': waiting for gnuplot failed: " + std::strerror(errno));

  const bool exited_ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
  const bool wrote = fs::exists(out_path, ec) && fs::file_size(out_path, ec) > 0;
  if (exited_ok && wrote) return;
  fs::remove(out_path, ec);  // gnuplot opens the output before it fails: no empty file left behind
  std::string why = WIFEXITED(status) ? "gnuplot exited with status " + std::to_string(WEXITSTATUS(status))
                                      : "gnuplot was killed by signal " + std::to_string(WTERMSIG(status));
  if (exited_ok) why = "gnuplot wrote nothing (is the directory there and writable?)";
  const std::string log = last_chars(slurp(log_path), 2000);
  throw Error("cannot draw '" + out_path + "': " + why + (log.empty() ? "" : ":\n" + log));
}

}  // namespace caustica
