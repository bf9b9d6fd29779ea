// The File menu's commands and what goes with them: new, open (a bundled
// example as an untitled copy), save and save as (atomic, through the
// session), the question before changes are lost, autosave and recovery
// after a crash, the window's layout, and files dropped on the window.

#include "MainWindow.hpp"
#include "RecentFilesMenu.hpp"
#include "kerf/document/DocumentEdits.hpp"
#include "kerf/document/DocumentError.hpp"
#include "kerf/document/UnknownFields.hpp"
#include "kerf/viewport/qt/ViewportWidget.hpp"

#include <QCloseEvent>
#include <QDir>
#include <QDragEnterEvent>
#include <QDropEvent>
#include <QFileDialog>
#include <QFileInfo>
#include <QMimeData>
#include <QSettings>
#include <QTimer>
#include <QTreeView>

namespace kerf::ui {

namespace fs = std::filesystem;

namespace {
bool isMeshFile(const QString& file)
{
    const QString s = QFileInfo(file).suffix().toLower();
    return s == "stl" || s == "obj" || s == "ply" || s == "off";
}
} // namespace

void MainWindow::reportError(const QString& title, const QString& message)
{
    if (options_.reportError) options_.reportError(title, message);
    else QMessageBox::warning(this, title, message);
}

QString MainWindow::askFile(bool saving, const QString& suggested)
{
    if (options_.askFile) return options_.askFile(saving, suggested);
    const QString filter = tr("Kerf documents (*.kerf)");
    if (saving) {
        QString f = QFileDialog::getSaveFileName(this, tr("Save As"), suggested, filter);
        if (!f.isEmpty() && !f.endsWith(".kerf")) f += ".kerf";
        return f;
    }
    return QFileDialog::getOpenFileName(this, tr("Open"), suggested, filter);
}

bool MainWindow::maybeSave()
{
    if (!session_->isModified()) return true;
    const QMessageBox::StandardButton answer =
        options_.askSave ? options_.askSave(session_->displayName())
                         : QMessageBox::warning(this, tr("Unsaved changes"),
                                                tr("%1 has changes that are not saved. Save them?").arg(session_->displayName()),
                                                QMessageBox::Save | QMessageBox::Discard | QMessageBox::Cancel,
                                                QMessageBox::Save);
    if (answer == QMessageBox::Cancel) return false;
    if (answer == QMessageBox::Save) return save();
    return true;
}

void MainWindow::newDocument()
{
    if (!maybeSave()) return;
    session_->reset(edit::emptyDocument(), std::nullopt);
    untitledStem_ = QStringLiteral("part");
    recovery_->clearAutosave();
    viewport_->setStandardView("iso");
    showMessage(tr("New part: add a feature from the Add menu or the toolbar."));
}

bool MainWindow::isBundledExample(const fs::path& file) const
{
    if (!options_.examplesFolder) return false;
    std::error_code ec;
    const fs::path folder = fs::weakly_canonical(*options_.examplesFolder, ec);
    const fs::path parent = fs::weakly_canonical(file, ec).parent_path();
    return !ec && parent == folder;
}

bool MainWindow::openFile(const fs::path& file)
{
    // The file is read first: one that cannot be opened leaves the part as
    // it is, without asking about its changes (a newcomer was asked to save
    // before being told that a PNG was no Kerf document).
    Document doc;
    try {
        doc = Document::load(file);
    } catch (const DocumentError& e) {
        showMessageUntilEdit(QString::fromUtf8(e.what()));
        reportError(tr("Cannot open"), QString::fromUtf8(e.what()));
        return false;
    }
    if (!maybeSave()) return false;
    {
        // A misspelt field ("transfom") loads, and the part goes without it:
        // said on opening, until the first edit.
        const std::vector<UnknownField> unknown = unknownFields(doc);
        // A bundled example opens as an untitled copy: Save asks where to
        // keep it instead of overwriting the installed file.
        const bool example = isBundledExample(file);
        session_->reset(std::move(doc), example ? std::nullopt : std::optional<fs::path>(file));
        untitledStem_ = example ? QString::fromStdString(file.stem().string()) : QStringLiteral("part");
        recovery_->clearAutosave();
        if (!example) recentFiles_->add(file);
        if (unknown.empty())
            showMessage(example ? tr("Opened a copy of the example %1: Save asks where to keep it.")
                                      .arg(QString::fromStdString(file.filename().string()))
                                : tr("Opened %1").arg(QString::fromStdString(file.string())));
        else
            showMessageUntilEdit(tr("Opened %1, but %2")
                                     .arg(QString::fromStdString(file.filename().string()),
                                          QString::fromStdString(summarizeUnknownFields(unknown))));
        tree_->collapseAll();
        tree_->expandToDepth(1);
        QTimer::singleShot(0, viewport_, [this] { viewport_->setStandardView("iso"); });
        return true;
    }
}

bool MainWindow::save()
{
    if (!session_->path()) return saveAs();
    return saveAs(*session_->path());
}

bool MainWindow::saveAs(const std::optional<fs::path>& file)
{
    fs::path target;
    if (file) {
        target = *file;
    } else {
        const QString folder = RecentFilesMenu::lastFolder();
        const QString suggested = session_->path() ? QString::fromStdString(session_->path()->string())
                                                   : (folder.isEmpty() ? QDir::homePath() : folder) + "/" + untitledStem_ +
                                                         ".kerf";
        const QString f = askFile(true, suggested);
        if (f.isEmpty()) return false;
        target = f.toStdString();
    }
    try {
        session_->saveAs(target);
        recovery_->clearAutosave();
        autosavedRevision_ = session_->revision();
        recentFiles_->add(target);
        showMessage(tr("Saved %1").arg(QString::fromStdString(target.string())));
        return true;
    } catch (const std::exception& e) {
        showMessageUntilEdit(tr("Not saved: %1").arg(QString::fromUtf8(e.what())));
        reportError(tr("Cannot save"), QString::fromUtf8(e.what()));
        return false;
    }
}

void MainWindow::autosaveNow()
{
    const Document& doc = session_->document();
    if (!session_->isModified() || session_->revision() == autosavedRevision_) return;
    if (doc.root.children.empty() && isBoolean(doc.root.type)) return; // nothing worth keeping yet
    try {
        recovery_->autosave(doc, session_->path());
        autosavedRevision_ = session_->revision();
    } catch (const std::exception& e) {
        showMessage(tr("Autosave failed: %1").arg(QString::fromUtf8(e.what())));
    }
}

void MainWindow::offerRecovery()
{
    std::vector<RecoveryCandidate> orphans = recovery_->orphans();
    std::sort(orphans.begin(), orphans.end(),
              [](const RecoveryCandidate& a, const RecoveryCandidate& b) { return a.savedAt > b.savedAt; });
    bool restored = false;
    for (const RecoveryCandidate& c : orphans) {
        bool restore = false;
        if (!restored) {
            if (options_.askRestore) {
                restore = options_.askRestore(c);
            } else {
                const QString what = c.original ? QString::fromStdString(c.original->string()) : tr("an unsaved part");
                restore = QMessageBox::question(
                              this, tr("Restore unsaved changes?"),
                              tr("Kerf did not close properly. Restore the changes to %1 autosaved at %2?")
                                  .arg(what, c.savedAt.toLocalTime().toString(Qt::TextDate)),
                              QMessageBox::Yes | QMessageBox::No, QMessageBox::Yes) == QMessageBox::Yes;
            }
        }
        if (restore) {
            try {
                Document doc = RecoveryStore::load(c);
                session_->reset(std::move(doc), c.original, /*modified=*/true);
                restored = true;
                // This session's own autosave holds it before the orphan goes:
                // a second crash before it is saved must not lose it.
                autosavedRevision_ = 0;
                autosaveNow();
                QTimer::singleShot(0, viewport_, [this] { viewport_->setStandardView("iso"); }); // frame it
                showMessage(tr("Restored the autosave of %1 — save it to keep it.").arg(session_->displayName()), 0);
            } catch (const std::exception& e) {
                showMessage(tr("The autosave could not be restored: %1").arg(QString::fromUtf8(e.what())), 0);
            }
        }
        recovery_->discard(c);
    }
}

void MainWindow::closeEvent(QCloseEvent* e)
{
    if (!maybeSave()) {
        e->ignore();
        return;
    }
    if (options_.rememberLayout) {
        QSettings settings;
        settings.setValue("window/geometry", saveGeometry());
        settings.setValue("window/state", saveState(kLayoutVersion));
    }
    e->accept();
}

void MainWindow::restoreLayout()
{
    if (!options_.rememberLayout) return;
    const QSettings settings;
    restoreGeometry(settings.value("window/geometry").toByteArray());
    restoreState(settings.value("window/state").toByteArray(), kLayoutVersion);
}

void MainWindow::dragEnterEvent(QDragEnterEvent* e)
{
    if (!e->mimeData()->hasUrls()) return;
    for (const QUrl& u : e->mimeData()->urls()) {
        const QString f = u.toLocalFile();
        if (f.endsWith(".kerf", Qt::CaseInsensitive) || isMeshFile(f)) {
            e->acceptProposedAction();
            return;
        }
    }
}

void MainWindow::dropEvent(QDropEvent* e)
{
    QStringList meshes;
    for (const QUrl& u : e->mimeData()->urls()) {
        const QString f = u.toLocalFile();
        if (f.endsWith(".kerf", Qt::CaseInsensitive)) {
            openFile(f.toStdString());
            e->acceptProposedAction();
            return;
        }
        if (isMeshFile(f)) meshes << f;
    }
    addMeshFiles(meshes);
    e->acceptProposedAction();
}

} // namespace kerf::ui
