#pragma once
// The main window: the feature tree (left), the viewport (centre), the
// property editor (right), the section and measure panels, menus and
// toolbars for every command, and a status bar that shows the
// voxelization's progress, the GPU memory, the frame time and the device.
//
// Its rooms: MainWindow.cpp (assembly, docks, document and selection,
// status), MainWindowCommands.cpp (menus and toolbars, grouped as the
// menus are), MainWindowFiles.cpp (the File menu's commands, autosave and
// recovery), MainWindowEdits.cpp (the Edit and Add menus' commands); the
// panels and tools are classes of their own (SectionPanel, StatusReadout,
// RecentFilesMenu, MeasureTool, MoveTool, SelectionGhosts).
//
// Everything the person does goes through the DocumentSession (undoable,
// validated); the voxelizer rebuilds in the background and the viewport
// streams what it publishes; files are saved atomically; the document is
// autosaved and offered back after a crash.

#include "DocumentSession.hpp"
#include "ExportDialog.hpp"
#include "Recovery.hpp"
#include "VoxelizerBridge.hpp"

#include <QMainWindow>
#include <QMessageBox>
#include <QPointer>

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <unordered_set>
#include <vector>

class QTreeView;
class QLabel;
class QTimer;
class QMenu;

namespace kerf::qt {
class ViewportWidget;
struct ViewportPick;
} // namespace kerf::qt

namespace kerf::ui {

class FeatureTreeModel;
class MeasureTool;
class MoveTool;
class SelectionGhosts;
class PropertyEditor;
class RecentFilesMenu;
class StatusReadout;
class ExportDialog;

struct MainWindowOptions {
    std::filesystem::path recoveryFolder = RecoveryStore::defaultFolder();
    int autosaveMs = 30000;
    /// Asked for each autosave left by a session that did not end cleanly;
    /// true restores it. Default: a question box.
    std::function<bool(const RecoveryCandidate&)> askRestore;
    /// Asked before changes would be lost: Save, Discard or Cancel.
    /// Default: a question box.
    std::function<QMessageBox::StandardButton(const QString& documentName)> askSave;
    /// Asked before an edit that may not be what was meant (a drop that
    /// changes what a difference cuts from): true goes on. Default: a
    /// question box.
    std::function<bool(const QString& question)> askConfirm;
    /// Asked for a file name (Save As, Open): empty cancels. Default: file dialogs.
    std::function<QString(bool save, const QString& suggested)> askFile;
    /// Tells of a refused open or save (the message also goes to the status
    /// bar). Default: a warning box.
    std::function<void(const QString& title, const QString& message)> reportError;
    /// The installed examples: a document opened from this folder opens as
    /// an untitled copy (Save asks where). None: every file opens as itself.
    std::optional<std::filesystem::path> examplesFolder;
    /// Restore the window's size and its docks and toolbars as the last
    /// session left them (QSettings), and save them on close.
    bool rememberLayout = true;
    /// Voxelize on the GPU (View menu), overriding the setting; none: the
    /// setting, which starts on where the viewport has a real GPU.
    std::optional<bool> voxelizeOnGpu;
};

class MainWindow : public QMainWindow {
    Q_OBJECT
public:
    explicit MainWindow(MainWindowOptions options = {});
    ~MainWindow() override;

    DocumentSession* session() { return session_; }
    qt::ViewportWidget* viewport() { return viewport_; }
    QTreeView* featureTree() { return tree_; }
    FeatureTreeModel* featureModel() { return model_; }
    PropertyEditor* propertyEditor() { return properties_; }
    VoxelizerBridge* voxelizer() { return voxelizer_; }
    RecoveryStore& recovery() { return *recovery_; }

    /// Opens a file (asking to save changes first). False when refused or
    /// cancelled; the reason goes to the status bar and a message box.
    bool openFile(const std::filesystem::path& file);
    /// Saves to the document's file (or asks where). False when cancelled or refused.
    bool save();
    bool saveAs(const std::optional<std::filesystem::path>& file = std::nullopt);
    void newDocument();
    /// Offers the autosaves of sessions that ended without closing.
    void offerRecovery();
    /// Writes the autosave now (the timer's work).
    void autosaveNow();

    /// Adds a feature of `type` where the selection says (inside a selected
    /// operation, else after the selected node, else in the root); selects it.
    bool addFeature(NodeType type);
    /// Puts the selected siblings under a new operation of `type`.
    bool groupSelection(NodeType type);
    bool deleteSelection();
    bool duplicateSelection();
    void selectNodes(const std::vector<std::string>& ids);
    std::vector<std::string> selectedNodeIds() const;

    /// The voxel memory budget (KERF_GPU_BUDGET_MB, the setting, or 1 GiB).
    std::size_t memoryBudgetBytes() const;
    /// Whether the document is voxelized on the GPU (View > Voxelize on the
    /// GPU, on a viewport that can): else by the CPU voxelizer.
    bool voxelizingOnGpu() const;

    /// The last message shown in the status bar's message area.
    QString lastMessage() const { return lastMessage_; }
    /// The measure panel's text (distance, or the bounding box).
    QString measureText() const;
    /// Whether the ghost of a selected tool is still being meshed.
    bool ghostsBusy() const;

protected:
    void closeEvent(QCloseEvent* e) override;
    void dragEnterEvent(QDragEnterEvent* e) override;
    void dropEvent(QDropEvent* e) override;

private:
    // What to do when a deletion takes away what a difference cuts from.
    enum class BaseDeletion { Cancel, WholeDifference, OnlySelection };
    BaseDeletion askDeletingABase(const Node& difference, const Node* after);
    /// A voxelized part with nothing in it, from a document that has
    /// features: said in the status bar, with what to change.
    void sayWhenNothingShows(const VoxelSnapshot& snapshot);
    /// Where a file made from the document goes first: beside it, named after it.
    std::filesystem::path suggestedFile(const char* extension) const;
    static constexpr int kLayoutVersion = 2; // saveState's version: bump when the docks change
    void restoreLayout();
    bool isBundledExample(const std::filesystem::path& file) const;
    // MainWindowCommands.cpp: one function per menu.
    QAction* newAction(const QString& text, const QString& name, const QKeySequence& key = {});
    void buildActions();
    void buildFileMenu();
    void buildEditMenu();
    void buildAddMenu();
    void buildViewMenu();
    void buildToolsMenu();
    void buildToolbars();
    void buildTreeContextMenu();
    void showExportDialog();
    void buildDocks();
    void buildStatusBar();
    void onDocumentChanged();
    /// Hands the document (its `tape`, null when it did not compile) to the
    /// voxelizer in use: the GPU's, through the viewport, or the CPU's.
    void voxelize(const Document& doc, std::shared_ptr<const Tape> tape);
    void voxelizeAgain();
    void onSelectionChanged();
    void onViewportClicked(const qt::ViewportPick& pick);
    void updateTitle();
    void updateStatus();
    void showMessage(const QString& text, int timeoutMs = 6000);
    /// A failure the status bar keeps until the part is next changed (a
    /// "Not saved: ..." stayed on through later edits).
    void showMessageUntilEdit(const QString& text);
    bool maybeSave();
    void addMeshFiles(const QStringList& files);
    QString askFile(bool save, const QString& suggested);
    void reportError(const QString& title, const QString& message);

    MainWindowOptions options_;
    QString untitledStem_ = QStringLiteral("part"); // Save As's suggestion for an untitled document
    DocumentSession* session_;
    VoxelizerBridge* voxelizer_;
    std::unique_ptr<RecoveryStore> recovery_;
    qt::ViewportWidget* viewport_;
    QTreeView* tree_;
    FeatureTreeModel* model_;
    PropertyEditor* properties_;
    RecentFilesMenu* recentFiles_ = nullptr;
    // The actions that appear in more than one place (menu, toolbar, context menu).
    struct Commands {
        QAction* newDocument = nullptr;
        QAction* open = nullptr;
        QAction* save = nullptr;
        QAction* exportPart = nullptr;
        QAction* undo = nullptr;
        QAction* redo = nullptr;
        QAction* remove = nullptr;
        QAction* duplicate = nullptr;
        QAction* rename = nullptr;
        QAction* fitAll = nullptr;
        QAction* orthographic = nullptr;
        QAction* exactEdges = nullptr;
        QMenu* add = nullptr;
        QMenu* group = nullptr;
        QMenu* view = nullptr;
        std::vector<QAction*> primitives, operations;
    } commands_;
    QTimer* autosave_;
    QTimer* progressTimer_;
    std::uint64_t autosavedRevision_ = 0;
    std::vector<MeshReference> loadedMeshes_;
    std::vector<std::string> expanded_;
    std::unordered_set<std::string> inTreeBeforeReset_;
    std::vector<std::string> selectionBeforeReset_;
    bool resettingTree_ = false;

    // Measure.
    QAction* measureAction_ = nullptr;
    QAction* refineForView_ = nullptr;
    QAction* voxelizeOnGpu_ = nullptr;
    std::optional<GridLayout> gpuLayout_; // the grid of the last GPU request (none: the CPU voxelizes)
    std::optional<Document> gpuDocument_; // ... and its document: the next one's dirty tiles are against it
    std::uint64_t gpuRevision_ = 0;       // counts GPU requests
    QLabel* measureLabel_ = nullptr;
    MeasureTool* measure_ = nullptr;
    MoveTool* move_ = nullptr;
    SelectionGhosts* ghosts_ = nullptr;

    // Status bar.
    StatusReadout* status_ = nullptr;
    QPointer<ExportDialog> exportDialog_; // the one open, if any (showExportDialog)
    // The export dialog's choices when it last wrote a file, and the
    // document they were for (none: an unsaved one): it opens with them
    // again for that document.
    std::optional<std::pair<std::optional<std::filesystem::path>, ExportChoices>> lastExport_;
    QString lastMessage_;
    QString messageUntilEdit_;
};

} // namespace kerf::ui
