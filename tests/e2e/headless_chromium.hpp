#pragma once

// Opens a report in Debian's headless Chromium, as a reader would, and reads back what the page's
// load handler recorded on <body> (docs/report.md): images on the page, images that failed to
// decode, script errors. A screenshot is kept in the build tree's test-artefacts/ folder.

#include <cstdlib>
#include <filesystem>
#include <string>

#include "run_emrm.hpp"

namespace emrm::e2e {

struct BrowserView {
  bool available = false;  ///< Chromium is installed
  bool loaded = false;     ///< the page's load handler ran
  int images = 0, broken_images = 0, errors = 0;
  std::string log;  ///< Chromium's stderr with console logging
  std::filesystem::path screenshot;
};

inline std::string chromium_binary() {
  for (const char* c : {"/usr/bin/chromium", "/usr/bin/chromium-browser"})
    if (std::filesystem::exists(c)) return c;
  return {};
}

/// Screenshots `html` into test-artefacts/NAME.png and dumps its DOM after loading.
inline BrowserView open_in_chromium(const std::filesystem::path& html, const std::string& name) {
  BrowserView view;
  const std::string chromium = chromium_binary();
  if (chromium.empty()) return view;
  view.available = true;
  const std::filesystem::path artefacts = std::filesystem::path(EMRM_TEST_ARTEFACTS);
  std::filesystem::create_directories(artefacts);
  view.screenshot = artefacts / (name + ".png");
  const auto work = html.parent_path();
  const std::string url = "file://" + std::filesystem::absolute(html).string();
  const std::string flags =
      "--headless --no-sandbox --disable-gpu --disable-dev-shm-usage --virtual-time-budget=10000 ";
  const auto log = work / (name + "-chromium.log");
  const auto dom = work / (name + "-dom.html");
  if (std::system((chromium + " " + flags + "--window-size=1280,2000 --screenshot=" + quoted(view.screenshot) + " " +
                   url + " > /dev/null 2> " + quoted(log))
                      .c_str()) != 0 ||
      std::system((chromium + " " + flags + "--enable-logging=stderr --dump-dom " + url + " > " + quoted(dom) + " 2> " +
                   quoted(log))
                      .c_str()) != 0) {
    view.log = read_text(log);
    return view;
  }
  view.log = read_text(log);
  const std::string page = read_text(dom);
  const auto body_at = page.find("<body");
  if (body_at == std::string::npos) return view;
  const std::string body = page.substr(body_at, page.find('>', body_at) - body_at + 1);
  const auto attribute = [&](const std::string& key) {
    const auto at = body.find(key + "=\"");
    if (at == std::string::npos) return -1;
    const auto start = at + key.size() + 2;
    return std::atoi(body.substr(start, body.find('"', start) - start).c_str());
  };
  view.images = attribute("data-images");
  view.loaded = view.images >= 0;
  view.broken_images = attribute("data-broken-images");
  view.errors = attribute("data-errors");
  return view;
}

}  // namespace emrm::e2e
