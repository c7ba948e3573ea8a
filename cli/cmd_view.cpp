// physik view RUN_DIR...: one self-contained HTML page that plays the run folders in 3D,
// overlaid in distinct colours (viewer/view_page.h). Bad input exits 2 naming the folder.
#include <filesystem>
#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "viewer/view_page.h"

namespace physik::cli {

namespace {

struct ViewCliOptions {
  std::vector<std::string> runs;
  std::string out;  // "" = <first run folder>/view.html
  viewer::ViewOptions view;
};

void run_view(const ViewCliOptions& o) {
  const std::string out =
      !o.out.empty() ? o.out : (std::filesystem::path(o.runs.at(0)) / "view.html").string();
  const std::size_t bytes = viewer::write_view_page(o.runs, o.view, out);
  std::cerr << "view: " << o.runs.size() << (o.runs.size() == 1 ? " run" : " runs") << ", "
            << bytes / 1024 << " KB -> " << out << "\n";
}

}  // namespace

void add_view_commands(CLI::App& app) {
  auto opt = std::make_shared<ViewCliOptions>();
  auto* cmd = app.add_subcommand(
      "view",
      "Write one self-contained HTML page that plays run folders (physik simulate --out DIR; "
      "simulate --reference adds DIR/mujoco) in 3D: the rigs as capsules, several runs "
      "overlaid in distinct colours, play/pause, a frame slider, speed, targets and their "
      "paths, kinetic energy and the largest residual per frame, bones past a joint limit "
      "highlighted. three.js r111 (Debian's libjs-three) is inlined: the page needs no "
      "network. Exit 2 for a folder that is not a run folder, an empty trajectory, or runs "
      "whose rigs have different bones.");
  cmd->add_option("RUN_DIR", opt->runs, "Run folders to overlay (the same bones)")->required();
  cmd->add_option("--out", opt->out, "The HTML file (default: RUN_DIR/view.html of the first)");
  cmd->add_option("--title", opt->view.title, "The page's title (default: the labels)");
  cmd->add_option("--label", opt->view.labels,
                  "A legend name per run folder, in order (default: each folder's name)");
  cmd->add_option("--max-frames", opt->view.max_frames,
                  "Frames kept per run; a longer run is decimated to this many rows, evenly "
                  "spread (the first and the last among them), and the page says so")
      ->capture_default_str();
  cmd->callback([opt] { run_view(*opt); });
}

}  // namespace physik::cli
