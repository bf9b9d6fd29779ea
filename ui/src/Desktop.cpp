#include "kerf/ui/Desktop.hpp"

#include "MainWindow.hpp"

#include <QApplication>
#include <QTimer>

#include <iostream>

namespace kerf::ui {

int runDesktop(int argc, char** argv, const std::optional<std::filesystem::path>& file,
               const std::filesystem::path& defaultExample)
{
    QApplication app(argc, argv);
    QApplication::setApplicationName("Kerf");
    QApplication::setOrganizationName("Kerf");
    QApplication::setApplicationVersion(KERF_VERSION);
    MainWindowOptions options;
    options.examplesFolder = defaultExample.parent_path();
    MainWindow window(std::move(options));
    window.show();
    const std::filesystem::path toOpen = file ? *file : defaultExample;
    if (!window.openFile(toOpen) && file) std::cerr << "kerf: could not open " << toOpen.string() << "\n";
    // After the window is up: offer what a crashed session left behind.
    QTimer::singleShot(0, &window, [&window] { window.offerRecovery(); });
    return app.exec();
}

} // namespace kerf::ui
