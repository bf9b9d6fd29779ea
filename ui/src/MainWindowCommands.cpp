// The main window's commands, grouped as their menus are: File, Edit, Add,
// View, Tools, then the toolbars and the tree's context menu, which reuse
// the menus' actions. What each command does lives in MainWindowFiles.cpp
// (File), MainWindowEdits.cpp (Edit, Add) and the tools' own classes; the
// rules behind the edits live in the core (document/).

#include "CutListDialog.hpp"
#include "ExportDialog.hpp"
#include "LengthDisplay.hpp"
#include "MainWindow.hpp"
#include "MeasureTool.hpp"
#include "MoveTool.hpp"
#include "NodeText.hpp"
#include "RecentFilesMenu.hpp"
#include "kerf/document/NodeTypes.hpp"
#include "kerf/viewport/qt/ViewportWidget.hpp"

#include <QAction>
#include <QActionGroup>
#include <QDir>
#include <QDockWidget>
#include <QFileDialog>
#include <QInputDialog>
#include <QMenu>
#include <QMenuBar>
#include <QSettings>
#include <QToolBar>
#include <QTreeView>

namespace kerf::ui {

namespace fs = std::filesystem;

namespace {

// The platform's bindings of the standard keys, then the extra ones, each
// key once (Qt ignores a shortcut bound twice as ambiguous).
QList<QKeySequence> uniqueShortcuts(std::initializer_list<QKeySequence::StandardKey> standard,
                                    std::initializer_list<QKeySequence> extra)
{
    QList<QKeySequence> keys;
    for (const QKeySequence::StandardKey k : standard)
        for (const QKeySequence& s : QKeySequence::keyBindings(k))
            if (!keys.contains(s)) keys.append(s);
    for (const QKeySequence& s : extra)
        if (!keys.contains(s)) keys.append(s);
    return keys;
}

// The node types of one kind, in the table's order (NodeTypes.hpp).
std::vector<NodeType> nodeTypesWhere(bool primitive)
{
    std::vector<NodeType> types;
    for (const NodeTypeSpec& spec : nodeTypeSpecs())
        if ((spec.category == NodeCategory::Primitive) == primitive) types.push_back(spec.type);
    return types;
}

QString objectNameFor(const char* prefix, NodeType t)
{
    return QString(prefix) + QString::fromUtf8(nodeTypeName(t).data(), qsizetype(nodeTypeName(t).size()));
}

} // namespace

QAction* MainWindow::newAction(const QString& text, const QString& name, const QKeySequence& key)
{
    auto* a = new QAction(text, this);
    a->setObjectName(name);
    if (!key.isEmpty()) a->setShortcut(key);
    addAction(a);
    return a;
}

void MainWindow::buildActions()
{
    buildFileMenu();
    buildEditMenu();
    buildAddMenu();
    buildViewMenu();
    buildToolsMenu();
    buildToolbars();
    buildTreeContextMenu();
}

void MainWindow::buildFileMenu()
{
    QMenu* file = menuBar()->addMenu(tr("&File"));
    commands_.newDocument = newAction(tr("&New"), "action.new", QKeySequence::New);
    connect(commands_.newDocument, &QAction::triggered, this, &MainWindow::newDocument);
    commands_.open = newAction(tr("&Open…"), "action.open", QKeySequence::Open);
    connect(commands_.open, &QAction::triggered, this, [this] {
        // In the open document's folder, else the last file's (it started in
        // the folder Kerf was started from, whatever the person had used).
        const QString folder = session_->path()
                                   ? QString::fromStdString(session_->path()->parent_path().string())
                                   : RecentFilesMenu::lastFolder();
        const QString f = askFile(false, folder);
        if (!f.isEmpty()) openFile(f.toStdString());
    });
    recentFiles_ = new RecentFilesMenu(this);
    connect(recentFiles_, &RecentFilesMenu::openRequested, this, [this](const fs::path& f) { openFile(f); });
    commands_.save = newAction(tr("&Save"), "action.save", QKeySequence::Save);
    connect(commands_.save, &QAction::triggered, this, [this] { save(); });
    QAction* saveAs = newAction(tr("Save &As…"), "action.saveAs", QKeySequence::SaveAs);
    connect(saveAs, &QAction::triggered, this, [this] { this->saveAs(); });
    commands_.exportPart = newAction(tr("&Export (STL, 3MF)…"), "action.export", QKeySequence(tr("Ctrl+E")));
    commands_.exportPart->setIconText(tr("Export…")); // the toolbar keeps its width
    connect(commands_.exportPart, &QAction::triggered, this, &MainWindow::showExportDialog);
    QAction* cutList = newAction(tr("&Cut List…"), "action.cutList");
    connect(cutList, &QAction::triggered, this, [this] {
        auto* d = new CutListDialog(session_->document(), session_->displayName(),
                                    QString::fromStdString(suggestedFile(".csv").string()), this);
        d->setObjectName("cutListDialog");
        d->setAttribute(Qt::WA_DeleteOnClose);
        d->show();
    });
    QAction* quit = newAction(tr("&Quit"), "action.quit", QKeySequence::Quit);
    connect(quit, &QAction::triggered, this, &QWidget::close);
    file->addActions({commands_.newDocument, commands_.open});
    file->addMenu(recentFiles_);
    file->addActions({commands_.save, saveAs});
    file->addSeparator();
    file->addActions({commands_.exportPart, cutList});
    file->addSeparator();
    file->addAction(quit);
}

void MainWindow::buildEditMenu()
{
    QMenu* edit = menuBar()->addMenu(tr("&Edit"));
    commands_.undo = session_->undoStack()->createUndoAction(this, tr("&Undo"));
    commands_.undo->setObjectName("action.undo");
    commands_.undo->setShortcuts(uniqueShortcuts({QKeySequence::Undo}, {QKeySequence(tr("Ctrl+Z"))}));
    // The toolbar shows the word alone: "Undo Set size" would widen the
    // button with every edit and push the others into the overflow. The
    // whole command stays in the menu and the tooltip.
    commands_.undo->setIconText(tr("Undo"));
    commands_.redo = session_->undoStack()->createRedoAction(this, tr("&Redo"));
    commands_.redo->setObjectName("action.redo");
    // Both spellings everywhere (the platform's binding may hold one of them
    // already: a key given twice is an ambiguous shortcut, and does nothing).
    commands_.redo->setShortcuts(
        uniqueShortcuts({QKeySequence::Redo}, {QKeySequence(tr("Ctrl+Shift+Z")), QKeySequence(tr("Ctrl+Y"))}));
    commands_.redo->setIconText(tr("Redo"));
    addActions({commands_.undo, commands_.redo});
    commands_.remove = newAction(tr("&Delete"), "action.delete", QKeySequence::Delete);
    connect(commands_.remove, &QAction::triggered, this, [this] { deleteSelection(); });
    commands_.duplicate = newAction(tr("D&uplicate"), "action.duplicate", QKeySequence(tr("Ctrl+D")));
    connect(commands_.duplicate, &QAction::triggered, this, [this] { duplicateSelection(); });
    commands_.rename = newAction(tr("Re&name"), "action.rename", QKeySequence(Qt::Key_F2));
    connect(commands_.rename, &QAction::triggered, this, [this] {
        if (tree_->currentIndex().isValid()) tree_->edit(tree_->currentIndex().siblingAtColumn(0));
    });
    edit->addActions({commands_.undo, commands_.redo});
    edit->addSeparator();
    edit->addActions({commands_.remove, commands_.duplicate, commands_.rename});
}

// Primitives and operations from the node type table, also on the feature
// toolbar and the tree's context menu.
void MainWindow::buildAddMenu()
{
    commands_.add = menuBar()->addMenu(tr("&Add"));
    commands_.group = new QMenu(tr("&Group Selection Under"), this);
    for (NodeType t : nodeTypesWhere(true)) {
        QAction* a = newAction(nodeTypeLabel(t), objectNameFor("action.add.", t));
        connect(a, &QAction::triggered, this, [this, t] { addFeature(t); });
        commands_.primitives.push_back(a);
        commands_.add->addAction(a);
    }
    commands_.add->addSeparator();
    for (NodeType t : nodeTypesWhere(false)) {
        QAction* a = newAction(nodeTypeLabel(t), objectNameFor("action.add.", t));
        connect(a, &QAction::triggered, this, [this, t] { addFeature(t); });
        commands_.operations.push_back(a);
        commands_.add->addAction(a);
        QAction* g = newAction(nodeTypeLabel(t), objectNameFor("action.group.", t));
        connect(g, &QAction::triggered, this, [this, t] { groupSelection(t); });
        commands_.group->addAction(g);
    }
    commands_.add->addSeparator();
    commands_.add->addMenu(commands_.group);
    QAction* mesh = newAction(tr("Reference &Mesh…"), "action.addMesh");
    connect(mesh, &QAction::triggered, this, [this] {
        addMeshFiles(QFileDialog::getOpenFileNames(this, tr("Add reference meshes"), {},
                                                   tr("Meshes (*.stl *.obj *.ply *.off)")));
    });
    commands_.add->addAction(mesh);
}

void MainWindow::buildViewMenu()
{
    commands_.view = menuBar()->addMenu(tr("&View"));
    QMenu* view = commands_.view;
    for (const auto& [name, label, key] :
         {std::tuple{"iso", tr("&Isometric"), QKeySequence(tr("0"))},
          std::tuple{"front", tr("&Front"), QKeySequence(tr("1"))},
          std::tuple{"back", tr("&Back"), QKeySequence(tr("Ctrl+1"))},
          std::tuple{"right", tr("&Right"), QKeySequence(tr("3"))},
          std::tuple{"left", tr("&Left"), QKeySequence(tr("Ctrl+3"))},
          std::tuple{"top", tr("&Top"), QKeySequence(tr("7"))},
          std::tuple{"bottom", tr("Botto&m"), QKeySequence(tr("Ctrl+7"))}}) {
        // The opposite view on Ctrl and the same key, as in Blender (a
        // newcomer looked for a key to see a board's underside).
        // Shown in the menu (a newcomer found the keys only in the README),
        // and answered anywhere in the window as F and 5 are: the action is
        // the window's too (a shortcut of the menu's alone answered only in
        // the view, and 1 did nothing with the feature tree in focus).
        QAction* a = newAction(label, QString("action.view.") + name, key);
        a->setShortcutContext(Qt::WidgetWithChildrenShortcut);
        const QString n = name;
        connect(a, &QAction::triggered, this, [this, n] { viewport_->setStandardView(n); });
        view->addAction(a);
    }
    view->addSeparator();
    commands_.fitAll = newAction(tr("&Fit All"), "action.fitAll", QKeySequence(tr("F")));
    commands_.fitAll->setShortcutContext(Qt::WidgetWithChildrenShortcut);
    connect(commands_.fitAll, &QAction::triggered, viewport_, &qt::ViewportWidget::fitAll);
    commands_.orthographic = newAction(tr("&Orthographic"), "action.orthographic", QKeySequence(tr("5")));
    commands_.orthographic->setShortcutContext(Qt::WidgetWithChildrenShortcut);
    commands_.orthographic->setCheckable(true);
    connect(commands_.orthographic, &QAction::toggled, viewport_, &qt::ViewportWidget::setOrthographic);
    // Key 5 in the view switches it there: the menu's and toolbar's check mark follows.
    connect(viewport_, &qt::ViewportWidget::orthographicChanged, commands_.orthographic, &QAction::setChecked);
    QAction* grid = newAction(tr("&Grid"), "action.grid");
    grid->setCheckable(true);
    grid->setChecked(true);
    connect(grid, &QAction::toggled, viewport_, &qt::ViewportWidget::setGridVisible);
    QAction* axes = newAction(tr("&Axes"), "action.axes");
    axes->setCheckable(true);
    axes->setChecked(true);
    connect(axes, &QAction::toggled, viewport_, &qt::ViewportWidget::setAxesVisible);
    commands_.exactEdges = newAction(tr("&Exact Edges"), "action.exactEdges", QKeySequence(tr("E")));
    commands_.exactEdges->setShortcutContext(Qt::WidgetWithChildrenShortcut);
    commands_.exactEdges->setCheckable(true);
    commands_.exactEdges->setToolTip(tr("Sharpen edges and intersections from the exact field near the surface (slower)"));
    connect(commands_.exactEdges, &QAction::toggled, viewport_, &qt::ViewportWidget::setExactEdges);
    view->addActions({commands_.fitAll, commands_.orthographic});
    view->addSeparator();
    // The seed's brick renderer, for comparing: measured slower than the
    // tracer on every scene (docs/benchmarks.md), so off by default.
    QAction* bricks = newAction(tr("&Brick Renderer"), "action.brickRenderer");
    bricks->setCheckable(true);
    bricks->setToolTip(tr("Draw the part as bricks of voxels, one cube each, marched by the texture unit (Vulkan; "
                          "slower than the default tracer; voxels only: Exact Edges switch back to the tracer)"));
    connect(bricks, &QAction::toggled, viewport_, &qt::ViewportWidget::setBrickRenderer);
    view->addActions({grid, axes, commands_.exactEdges, bricks});
    view->addSeparator();
    // Modelling only what the scene requires: tiles as fine as the camera
    // sees them, within a memory budget.
    refineForView_ = newAction(tr("&Refine Only What the View Needs"), "action.refineForView");
    refineForView_->setCheckable(true);
    refineForView_->setChecked(QSettings().value("refineForView", true).toBool());
    connect(refineForView_, &QAction::toggled, this, [this](bool on) {
        QSettings().setValue("refineForView", on);
        voxelizer_->setView(on ? viewport_->settledView() : std::nullopt);
    });
    QAction* budget = newAction(tr("Voxel Memory &Budget…"), "action.memoryBudget");
    connect(budget, &QAction::triggered, this, [this] {
        bool ok = false;
        const int mb = QInputDialog::getInt(this, tr("Voxel memory budget"),
                                            tr("Largest voxel memory (MB). Past it, the farthest tiles are coarsened:"),
                                            int(memoryBudgetBytes() >> 20), 16, 1 << 20, 64, &ok);
        if (!ok) return;
        QSettings().setValue("voxelBudgetMB", mb);
        voxelizer_->voxelizer().setMemoryBudget(memoryBudgetBytes());
        voxelizeAgain();
    });
    // Where the voxels are built: the GPU (compute shaders, the whole part
    // at full depth in milliseconds) or the CPU (oneTBB, refined for the view).
    voxelizeOnGpu_ = newAction(tr("Voxelize on the &GPU"), "action.voxelizeOnGpu");
    voxelizeOnGpu_->setCheckable(true);
    voxelizeOnGpu_->setEnabled(viewport_->canVoxelizeOnGpu());
    voxelizeOnGpu_->setToolTip(viewport_->canVoxelizeOnGpu()
                                   ? tr("Build the voxels with compute shaders on the viewport's device")
                                   : tr("The viewport has no Vulkan device: the CPU voxelizes"));
    voxelizeOnGpu_->setChecked(options_.voxelizeOnGpu.value_or(
        QSettings().value("voxelizeOnGpu", viewport_->hasHardwareGpu()).toBool()));
    connect(voxelizeOnGpu_, &QAction::toggled, this, [this](bool on) {
        QSettings().setValue("voxelizeOnGpu", on);
        voxelizeAgain();
        if (!voxelizingOnGpu()) voxelizer_->setView(refineForView_->isChecked() ? viewport_->settledView() : std::nullopt);
    });
    view->addActions({refineForView_, budget, voxelizeOnGpu_});
    view->addSeparator();
    // How lengths are shown and typed (the document stays in millimetres).
    QMenu* lengths = view->addMenu(tr("&Lengths In"));
    auto* lengthUnits = new QActionGroup(this);
    for (const auto& [unit, label, name] :
         {std::tuple{LengthUnit::Millimetres, tr("&Millimetres"), "action.lengths.mm"},
          std::tuple{LengthUnit::Inches, tr("&Inches and Fractions"), "action.lengths.in"}}) {
        QAction* a = newAction(label, name);
        a->setCheckable(true);
        a->setChecked(LengthDisplay::instance().unit() == unit);
        a->setActionGroup(lengthUnits);
        const LengthUnit chosen = unit;
        connect(a, &QAction::triggered, this, [chosen] { LengthDisplay::instance().setUnit(chosen); });
        lengths->addAction(a);
    }
    view->addSeparator(); // the docks' toggles follow (buildDocks)
}

void MainWindow::buildToolsMenu()
{
    QMenu* tools = menuBar()->addMenu(tr("&Tools"));
    measureAction_ = newAction(tr("&Measure Distance"), "action.measure", QKeySequence(tr("M")));
    // Window-wide, so that it works with the viewport focused (a text field
    // still takes the letter: it overrides shortcuts for what it types).
    measureAction_->setShortcutContext(Qt::WindowShortcut);
    measureAction_->setCheckable(true);
    connect(measureAction_, &QAction::toggled, this, [this](bool on) {
        measure_->setActive(on);
        move_->setEnabled(!on);
        if (on)
            if (auto* dock = findChild<QDockWidget*>("dock.measure")) dock->raise();
    });
    QAction* bbox = newAction(tr("&Bounding Box"), "action.boundingBox", QKeySequence(tr("B")));
    bbox->setToolTip(tr("The bounding box of the selection (of the part when nothing is selected), in the view "
                        "and the Measure panel"));
    connect(bbox, &QAction::triggered, this, [this] {
        if (auto* dock = findChild<QDockWidget*>("dock.measure")) dock->raise();
        measure_->showBoundingBox(selectedNodeIds());
    });
    QAction* clear = newAction(tr("&Clear Measurement"), "action.clearMeasurement", QKeySequence(Qt::Key_Escape));
    // Esc belongs to whatever has the focus (an editor, a dialog); the viewport passes it on (escapePressed).
    clear->setShortcutContext(Qt::WidgetShortcut);
    connect(viewport_, &qt::ViewportWidget::escapePressed, clear, &QAction::trigger);
    connect(clear, &QAction::triggered, this, [this] {
        // Esc in the viewport: first a gizmo drag, then a measurement, then measuring itself.
        if (move_->dragging()) viewport_->cancelGizmoDrag();
        else if (!measure_->clear() && measureAction_->isChecked()) measureAction_->setChecked(false);
    });
    tools->addActions({measureAction_, bbox, clear});
}

void MainWindow::buildToolbars()
{
    QToolBar* fileBar = addToolBar(tr("File"));
    fileBar->setObjectName("toolbar.file");
    fileBar->addActions({commands_.newDocument, commands_.open, commands_.save, commands_.undo, commands_.redo,
                         commands_.exportPart});
    QToolBar* viewBar = addToolBar(tr("View"));
    viewBar->setObjectName("toolbar.view");
    viewBar->addActions({commands_.fitAll, commands_.orthographic, commands_.exactEdges, measureAction_});
    // The features on a row of their own: beside the others they ran past
    // the edge of a 1280-pixel-wide window into the overflow menu.
    addToolBarBreak();
    QToolBar* featureBar = addToolBar(tr("Features"));
    featureBar->setObjectName("toolbar.features");
    for (QAction* a : commands_.primitives) featureBar->addAction(a);
    featureBar->addSeparator();
    for (QAction* a : commands_.operations) featureBar->addAction(a);
}

void MainWindow::buildTreeContextMenu()
{
    connect(tree_, &QTreeView::customContextMenuRequested, this, [this](const QPoint& at) {
        QMenu menu(this);
        menu.addMenu(commands_.add);
        menu.addMenu(commands_.group);
        menu.addSeparator();
        menu.addActions({commands_.rename, commands_.duplicate, commands_.remove});
        menu.exec(tree_->viewport()->mapToGlobal(at));
    });
}

fs::path MainWindow::suggestedFile(const char* extension) const
{
    // Beside the document, named after it (an untitled part: in the home
    // folder, named after the example it came from or "part").
    fs::path file = session_->path() ? session_->path()->parent_path() / session_->path()->stem()
                                     : fs::path(QDir::homePath().toStdString()) / untitledStem_.toStdString();
    file += extension;
    return file;
}

void MainWindow::showExportDialog()
{
    const fs::path suggested = suggestedFile(".stl");
    // One export dialog: Export… again brings it forward (a newcomer had
    // three stacked on one another).
    if (exportDialog_) {
        exportDialog_->show();
        exportDialog_->raise();
        exportDialog_->activateWindow();
        return;
    }
    // The 3MF object's name: the document's file name, as kerf export gives it.
    const std::string partName = session_->path() ? session_->path()->stem().string() : std::string("part");
    // The choices of the last file written from this document, else the
    // suggestion beside it.
    ExportChoices choices;
    choices.file = suggested;
    const std::optional<fs::path> document = session_->path();
    if (lastExport_ && lastExport_->first == document) choices = lastExport_->second;
    auto* d = new ExportDialog([this] { return session_->document(); }, partName, choices, this);
    d->setObjectName("exportDialog");
    d->setSelection([this] { return selectedNodeIds(); });
    d->setAttribute(Qt::WA_DeleteOnClose);
    connect(d, &ExportDialog::finished, this, [this, d, document](const ExportOutcome& outcome) {
        if (outcome.written) lastExport_ = {document, d->choices()};
    });
    exportDialog_ = d;
    d->show();
}

} // namespace kerf::ui
