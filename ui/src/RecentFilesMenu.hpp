#pragma once
// File > Open Recent: the last eight documents opened or saved, newest
// first, kept in the settings ("recentFiles") across sessions; disabled
// while there are none.

#include <QMenu>

#include <filesystem>

namespace kerf::ui {

class RecentFilesMenu : public QMenu {
    Q_OBJECT
public:
    explicit RecentFilesMenu(QWidget* parent);

    /// Puts `file` first (once).
    void add(const std::filesystem::path& file);
    /// The folder of the file opened or saved last; empty when none.
    static QString lastFolder();

signals:
    void openRequested(const std::filesystem::path& file);

private:
    void rebuild();
};

} // namespace kerf::ui
