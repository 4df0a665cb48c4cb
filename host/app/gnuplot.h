// Drawing through gnuplot (Debian package gnuplot-nox). Figures with text in
// them (axes, tick labels, legends, colour bars) are left to that well-kept
// tool instead of hand-drawn glyphs. caustica writes the script and its data
// into a private temporary directory and runs `gnuplot SCRIPT` without a
// shell; a missing gnuplot, a failing script or a missing output file becomes
// a caustica::Error that names the output and carries gnuplot's own message.
// Text that comes from the user (file names) goes into scripts only through
// gnuplot_quote and is drawn `noenhanced`, so '_' and '^' stay literal.
#pragma once

#include <string>
#include <vector>

namespace caustica {

// A fresh directory under the system's temporary directory, removed with
// everything in it when this object goes away.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// True when an executable `gnuplot` is on PATH.
bool gnuplot_available();

// `text` as a gnuplot single-quoted string: nothing inside is interpreted
// except a doubled quote.
std::string gnuplot_quote(const std::string& text);

// `set terminal ...` and `set output ...` lines for out_path, by extension:
// .png (pngcairo) or .svg; width and height in pixels. Throws naming the path
// for any other extension.
std::string gnuplot_output(const std::string& out_path, int width, int height);

// The colour bar of draw_heatmap: viridis from lo to hi (lo < hi); values
// outside take the end colours.
struct ColourBar {
  double lo = 0.0, hi = 1.0;
  bool log_scale = false;
  std::string tic_format;  // `set format cb` (enhanced text); empty: gnuplot's
  double tic_step = 0.0;   // between ticks; 0: gnuplot's choice
  std::string label;       // drawn verbatim
  // Characters right of gnuplot's place for the label, which overlaps ticks
  // of plain numbers (it leaves room for '10^{%T}' ticks).
  double label_offset = 0.0;
};

// `values` (width x height, row-major, top row first) as a false-colour image
// with `bar` on its right, top row at the top. Whole pixels: small images are
// enlarged by an integer factor to about 400 pixels on their long side, so
// single pixels stay visible and square. `title` is drawn above verbatim.
// The values go to gnuplot through a temporary file.
void draw_heatmap(const std::vector<float>& values, int width, int height, const ColourBar& bar,
                  const std::string& title, const std::string& out_path);

// Runs gnuplot on `script`, which writes out_path (see gnuplot_output); files
// the script reads must already exist. A failed run leaves no out_path behind.
void run_gnuplot(const std::string& script, const std::string& out_path);

}  // namespace caustica
