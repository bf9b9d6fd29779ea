#include "RecentFilesMenu.hpp"

#include <QAction>
#include <QFileInfo>
#include <QSettings>

namespace kerf::ui {

namespace {
constexpr int kMaxRecentFiles = 8;
const char* const kKey = "recentFiles";
} // namespace

RecentFilesMenu::RecentFilesMenu(QWidget* parent) : QMenu(tr("Open &Recent"), parent) { rebuild(); }

QString RecentFilesMenu::lastFolder()
{
    const QStringList list = QSettings().value(kKey).toStringList();
    return list.isEmpty() ? QString() : QFileInfo(list.front()).absolutePath();
}

void RecentFilesMenu::add(const std::filesystem::path& file)
{
    QSettings settings;
    QStringList list = settings.value(kKey).toStringList();
    const QString f = QString::fromStdString(std::filesystem::absolute(file).string());
    list.removeAll(f);
    list.prepend(f);
    while (list.size() > kMaxRecentFiles) list.removeLast();
    settings.setValue(kKey, list);
    rebuild();
}

void RecentFilesMenu::rebuild()
{
    clear();
    const QStringList list = QSettings().value(kKey).toStringList();
    for (const QString& f : list) {
        QAction* a = addAction(QFileInfo(f).fileName());
        a->setToolTip(f);
        connect(a, &QAction::triggered, this, [this, f] { emit openRequested(f.toStdString()); });
    }
    setEnabled(!list.isEmpty());
}

} // namespace kerf::ui
