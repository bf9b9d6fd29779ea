// Screenshots of the desktop application for the documentation: opens a
// document in the real main window, waits until the viewport shows it at
// full depth, and saves the window with the viewport's frame painted in
// (a widget grab does not see the Vulkan window's pixels).
//
//   xvfb-run -a -s "-screen 0 1600x1000x24" build/ui/app-screenshot/kerf_app_screenshot
//       FILE.kerf OUT.png [--select NODE_ID] [--view iso|front|...] [--section x|y|z] [--size WxH]

#include "MainWindow.hpp"
#include "kerf/viewport/qt/ViewportWidget.hpp"

#include <QApplication>
#include <QCheckBox>
#include <QComboBox>
#include <QPainter>
#include <QTest>

#include <iostream>
#include <string>

using namespace kerf;
using namespace kerf::ui;

int main(int argc, char** argv)
{
    QApplication app(argc, argv);
    if (argc < 3) {
        std::cerr << "usage: kerf_app_screenshot FILE.kerf OUT.png [--select ID] [--view NAME] [--section x|y|z] [--size WxH]\n";
        return 2;
    }
    const std::string file = argv[1];
    const QString out = argv[2];
    std::string select, view = "iso", section;
    int width = 1440, height = 900;
    for (int i = 3; i + 1 < argc; i += 2) {
        const std::string a = argv[i], v = argv[i + 1];
        if (a == "--select") select = v;
        else if (a == "--view") view = v;
        else if (a == "--section") section = v;
        else if (a == "--size") std::sscanf(v.c_str(), "%dx%d", &width, &height);
    }
    MainWindowOptions options;
    options.recoveryFolder = std::filesystem::temp_directory_path() / "kerf-screenshot-recovery";
    options.reportError = [](const QString&, const QString& m) { std::cerr << m.toStdString() << "\n"; };
    MainWindow window(options);
    window.resize(width, height);
    window.show();
    if (!window.openFile(file)) return 1;
    if (!select.empty()) window.selectNodes({select});
    QTest::qWait(200);
    window.viewport()->setStandardView(QString::fromStdString(view));
    if (!section.empty()) {
        window.findChild<QCheckBox*>("section.enabled")->setChecked(true);
        window.findChild<QComboBox*>("section.axis")->setCurrentIndex(section == "x" ? 0 : section == "y" ? 1 : 2);
    }
    // Until what is shown is the document, complete, and nothing streams.
    const bool ready = QTest::qWaitFor(
        [&] {
            const auto snap = window.voxelizer()->latest();
            const auto s = window.viewport()->status();
            return snap && snap->complete && !window.voxelizer()->progress().busy && s.shownVersion >= snap->version &&
                   !s.streaming;
        },
        300000);
    if (!ready) {
        std::cerr << "kerf_app_screenshot: the viewport did not settle\n";
        return 1;
    }
    QTest::qWait(500); // the status bar and docks settle
    const QImage frame = window.viewport()->grabFrame();
    QPixmap shot = window.grab();
    QPainter p(&shot);
    p.drawImage(QRect(window.viewport()->mapTo(&window, QPoint(0, 0)), window.viewport()->size()), frame);
    p.end();
    if (!shot.save(out)) {
        std::cerr << "kerf_app_screenshot: cannot write " << out.toStdString() << "\n";
        return 1;
    }
    return 0;
}
