#include "frame_plot.hpp"

#include <sys/wait.h>

#include <cstdio>

namespace farfield {

namespace {

// Fed to Debian's `/usr/bin/python3 -` (python3-matplotlib) on stdin, so the binary needs no script
// installed beside it.
constexpr const char* kScript = R"PY(
import json, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
bench = json.load(open(sys.argv[1]))
fig, ax = plt.subplots(figsize=(10, 5), dpi=100)
for t in bench["techniques"]:
    ms = [f["frame_ms"] for f in t["frames"]]
    ax.plot(range(len(ms)), ms, label="%s (median %.1f ms)" % (t["name"], t["summary"]["median_ms"]), linewidth=1)
ax.set_xlabel("frame")
ax.set_ylabel("frame time (ms)")
ax.set_ylim(bottom=0)
s = bench["scene"]
ax.set_title("%s: %d triangles, %dx%d, %s" % (s["file"].split("/")[-1], s["triangles"], bench["width"], bench["height"], bench["renderer"]), fontsize=9)
ax.grid(True, alpha=0.3)
ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(sys.argv[2])
)PY";

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

}  // namespace

Result<void> plot_frame_times(const std::string& json_path, const std::string& png_path) {
  const std::string command =
      "/usr/bin/python3 - " + shell_quote(json_path) + " " + shell_quote(png_path) + " 2>&1";
  FILE* pipe = ::popen(command.c_str(), "w");
  if (!pipe) return make_error(png_path, ": cannot start python3 for the plot");
  std::fputs(kScript, pipe);
  const int status = ::pclose(pipe);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    return make_error(png_path,
                      ": the plot failed (python3 with matplotlib is needed: "
                      "scripts/install-deps.sh installs python3-matplotlib)");
  return {};
}

}  // namespace farfield
