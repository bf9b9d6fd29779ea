#include "MainWindow.hpp"

#include "CutListDialog.hpp"
#include "ExportDialog.hpp"
#include "FeatureTreeModel.hpp"
#include "MeasureTool.hpp"
#include "MoveTool.hpp"
#include "NodeText.hpp"
#include "PropertyEditor.hpp"
#include "QuantityEdit.hpp"
#include "SelectionGhosts.hpp"
#include "kerf/document/AddFeature.hpp"
#include "kerf/document/DocumentEdits.hpp"
#include "kerf/document/DocumentError.hpp"
#include "kerf/document/NodeTypes.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/viewport/ReferenceMesh.hpp"
#include "kerf/viewport/qt/ViewportWidget.hpp"

#include <QAction>
#include <QActionGroup>
#include <QApplication>
#include <QCheckBox>
#include <QCloseEvent>
#include <QComboBox>
#include <QDockWidget>
#include <QDragEnterEvent>
#include <QDropEvent>
#include <QFileDialog>
#include <QFileInfo>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QInputDialog>
#include <QLabel>
#include <QMenu>
#include <QMenuBar>
#include <QMimeData>
#include <QScrollArea>
#include <QSettings>
#include <QSignalBlocker>
#include <QSlider>
#include <QStatusBar>
#include <QTimer>
#include <QToolBar>
#include <QTreeView>
#include <QVBoxLayout>

#include <glm/glm.hpp>

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

constexpr int kMaxRecentFiles = 8;

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

bool isMeshFile(const QString& file)
{
    const QString s = QFileInfo(file).suffix().toLower();
    return s == "stl" || s == "obj" || s == "ply" || s == "off";
}

// Primitive node ids in a subtree: what the viewport highlights for a selection.
void collectFeatureNodes(const Node& n, std::unordered_set<std::string>& out)
{
    if (isPrimitive(n.type)) out.insert(n.id);
    for (const auto& c : n.children) collectFeatureNodes(c, out);
}

} // namespace

MainWindow::MainWindow(MainWindowOptions options) : options_(std::move(options))
{
    setObjectName("mainWindow");
    setAcceptDrops(true);
    session_ = new DocumentSession(this);
    {
        VoxelizerOptions vo;
        vo.memoryBudgetBytes = memoryBudgetBytes();
        voxelizer_ = new VoxelizerBridge(this, vo);
    }
    recovery_ = std::make_unique<RecoveryStore>(options_.recoveryFolder);
    model_ = new FeatureTreeModel(session_, this);

    viewport_ = new qt::ViewportWidget(this);
    viewport_->setObjectName("viewport");
    setCentralWidget(viewport_);

    tree_ = new QTreeView(this);
    tree_->setObjectName("featureTree");
    tree_->setModel(model_);
    tree_->setSelectionMode(QAbstractItemView::ExtendedSelection);
    tree_->setDragDropMode(QAbstractItemView::InternalMove);
    tree_->setDefaultDropAction(Qt::MoveAction);
    tree_->setDragEnabled(true);
    tree_->setAcceptDrops(true);
    tree_->setDropIndicatorShown(true);
    // Rename with F2 or Edit > Rename only: a click on the selected row
    // (to leave a field, say) must not open an editor that swallows Ctrl+Z.
    tree_->setEditTriggers(QAbstractItemView::EditKeyPressed);
    tree_->setContextMenuPolicy(Qt::CustomContextMenu);
    tree_->header()->setSectionResizeMode(0, QHeaderView::Stretch);
    tree_->header()->setSectionResizeMode(1, QHeaderView::ResizeToContents);
    tree_->header()->setStretchLastSection(false);
    tree_->setMinimumWidth(300);
    tree_->expandAll();

    properties_ = new PropertyEditor(session_, this);
    properties_->setObjectName("propertyEditor");

    buildActions();
    buildDocks();
    buildStatusBar();
    restoreLayout();

    measure_ = new MeasureTool(session_, viewport_, measureLabel_, this);
    connect(measure_, &MeasureTool::message, this, [this](const QString& m) { showMessage(m); });
    move_ = new MoveTool(session_, viewport_, this);
    connect(move_, &MoveTool::message, this, [this](const QString& m) {
        if (m.isEmpty()) statusBar()->clearMessage();
        else showMessage(m, 0);
    });
    ghosts_ = new SelectionGhosts(viewport_, this);

    connect(session_, &DocumentSession::documentChanged, this, &MainWindow::onDocumentChanged);
    connect(session_, &DocumentSession::stateChanged, this, &MainWindow::updateTitle);
    connect(model_, &QAbstractItemModel::modelAboutToBeReset, this, [this] {
        expanded_.clear();
        // Remember which rows are open and selected, by node id.
        std::function<void(const QModelIndex&)> walk = [&](const QModelIndex& parent) {
            for (int r = 0; r < model_->rowCount(parent); ++r) {
                const QModelIndex i = model_->index(r, 0, parent);
                if (tree_->isExpanded(i)) expanded_.push_back(model_->nodeIdAt(i));
                walk(i);
            }
        };
        walk({});
        selectionBeforeReset_ = selectedNodeIds();
        resettingTree_ = true; // the selection the view clears now is not the person's
    });
    connect(model_, &QAbstractItemModel::modelReset, this, [this] {
        resettingTree_ = false;
        for (const auto& id : expanded_) tree_->setExpanded(model_->indexOf(id), true);
        tree_->setExpanded(model_->index(0, 0), true);
        std::vector<std::string> keep;
        for (const auto& id : selectionBeforeReset_)
            if (session_->document().root.find(id)) keep.push_back(id);
        selectNodes(keep);
    });
    connect(tree_->selectionModel(), &QItemSelectionModel::selectionChanged, this, &MainWindow::onSelectionChanged);
    connect(model_, &FeatureTreeModel::editRefused, this, [this](const QString& why) { showMessage(why); });
    model_->setConfirm([this](const QString& question) {
        if (options_.askConfirm) return options_.askConfirm(question);
        return QMessageBox::question(this, tr("Reorder"), question, QMessageBox::Yes | QMessageBox::Cancel,
                                     QMessageBox::Cancel) == QMessageBox::Yes;
    });
    connect(viewport_, &qt::ViewportWidget::clicked, this, &MainWindow::onViewportClicked);
    connect(viewport_, &qt::ViewportWidget::frameDrawn, this, &MainWindow::updateStatus);
    connect(viewport_, &qt::ViewportWidget::backendChanged, this, [this] {
        showMessage(tr("The viewport uses the CPU reference tracer: %1").arg(viewport_->status().fallbackReason), 0);
    });
    connect(viewport_, &qt::ViewportWidget::viewSettled, this, [this](const ViewRequirement& v) {
        if (refineForView_->isChecked()) voxelizer_->setView(v);
    });
    connect(viewport_, &qt::ViewportWidget::pictureTaken, this, [this](std::shared_ptr<const OcclusionMap> picture) {
        if (refineForView_->isChecked()) voxelizer_->setOcclusion(std::move(picture));
    });
    connect(voxelizer_, &VoxelizerBridge::published, this, [this](std::shared_ptr<const VoxelSnapshot> s) {
        viewport_->setSnapshot(std::move(s));
        updateStatus();
    });

    autosave_ = new QTimer(this);
    autosave_->setInterval(options_.autosaveMs);
    connect(autosave_, &QTimer::timeout, this, &MainWindow::autosaveNow);
    autosave_->start();
    progressTimer_ = new QTimer(this);
    progressTimer_->setInterval(100);
    connect(progressTimer_, &QTimer::timeout, this, &MainWindow::updateStatus);
    progressTimer_->start();

    resize(1400, 860);
    onDocumentChanged();
    updateTitle();
    if (!viewport_->status().vulkan)
        showMessage(tr("No usable Vulkan device (%1): the viewport uses the CPU reference tracer.")
                        .arg(viewport_->status().fallbackReason),
                    0);
}

MainWindow::~MainWindow()
{
    // The children go after this body, the session among them (its undo
    // stack signals as it dies): none may call back into a window that is
    // no longer one.
    for (QObject* child : std::initializer_list<QObject*>{session_, voxelizer_, model_, viewport_, properties_})
        child->disconnect(this);
    autosave_->stop();
    progressTimer_->stop();
}

std::size_t MainWindow::memoryBudgetBytes() const
{
    // KERF_GPU_BUDGET_MB (tests, scripts), else the setting, else 1 GiB: a
    // fraction of any GPU Kerf runs on, and a scene far beyond what a screen shows.
    const QString env = qEnvironmentVariable("KERF_GPU_BUDGET_MB");
    const qlonglong mb = !env.isEmpty() ? env.toLongLong() : QSettings().value("voxelBudgetMB", 1024).toLongLong();
    return std::size_t(std::max<qlonglong>(mb, 1)) << 20;
}

// ---------------------------------------------------------------------------
// Actions, menus, toolbars

void MainWindow::buildActions()
{
    auto action = [this](const QString& text, const QString& name, const QKeySequence& key = {}) {
        auto* a = new QAction(text, this);
        a->setObjectName(name);
        if (!key.isEmpty()) a->setShortcut(key);
        addAction(a);
        return a;
    };

    // File
    QMenu* file = menuBar()->addMenu(tr("&File"));
    QAction* newAct = action(tr("&New"), "action.new", QKeySequence::New);
    connect(newAct, &QAction::triggered, this, &MainWindow::newDocument);
    QAction* openAct = action(tr("&Open…"), "action.open", QKeySequence::Open);
    connect(openAct, &QAction::triggered, this, [this] {
        const QString f = askFile(false, {});
        if (!f.isEmpty()) openFile(f.toStdString());
    });
    recentMenu_ = new QMenu(tr("Open &Recent"), this);
    QAction* saveAct = action(tr("&Save"), "action.save", QKeySequence::Save);
    connect(saveAct, &QAction::triggered, this, [this] { save(); });
    QAction* saveAsAct = action(tr("Save &As…"), "action.saveAs", QKeySequence::SaveAs);
    connect(saveAsAct, &QAction::triggered, this, [this] { saveAs(); });
    QAction* exportAct = action(tr("&Export (STL, 3MF)…"), "action.export", QKeySequence(tr("Ctrl+E")));
    exportAct->setIconText(tr("Export…")); // the toolbar keeps its width
    connect(exportAct, &QAction::triggered, this, [this] {
        fs::path suggested = session_->path() ? session_->path()->parent_path() / session_->path()->stem()
                                              : fs::path(QDir::homePath().toStdString()) / "part";
        suggested += ".stl";
        auto* d = new ExportDialog(session_->document(), suggested, this);
        d->setObjectName("exportDialog");
        d->setAttribute(Qt::WA_DeleteOnClose);
        d->show();
    });
    QAction* cutListAct = action(tr("&Cut List…"), "action.cutList");
    connect(cutListAct, &QAction::triggered, this, [this] {
        auto* d = new CutListDialog(session_->document(), session_->displayName(), this);
        d->setObjectName("cutListDialog");
        d->setAttribute(Qt::WA_DeleteOnClose);
        d->show();
    });
    QAction* quitAct = action(tr("&Quit"), "action.quit", QKeySequence::Quit);
    connect(quitAct, &QAction::triggered, this, &QWidget::close);
    file->addActions({newAct, openAct});
    file->addMenu(recentMenu_);
    file->addActions({saveAct, saveAsAct});
    file->addSeparator();
    file->addActions({exportAct, cutListAct});
    file->addSeparator();
    file->addAction(quitAct);
    rebuildRecentMenu();

    // Edit
    QMenu* edit = menuBar()->addMenu(tr("&Edit"));
    QAction* undoAct = session_->undoStack()->createUndoAction(this, tr("&Undo"));
    undoAct->setObjectName("action.undo");
    undoAct->setShortcuts(uniqueShortcuts({QKeySequence::Undo}, {QKeySequence(tr("Ctrl+Z"))}));
    // The toolbar shows the word alone: "Undo Set size" would widen the
    // button with every edit and push the others into the overflow. The
    // whole command stays in the menu and the tooltip.
    undoAct->setIconText(tr("Undo"));
    QAction* redoAct = session_->undoStack()->createRedoAction(this, tr("&Redo"));
    redoAct->setObjectName("action.redo");
    // Both spellings everywhere (the platform's binding may hold one of them
    // already: a key given twice is an ambiguous shortcut, and does nothing).
    redoAct->setShortcuts(
        uniqueShortcuts({QKeySequence::Redo}, {QKeySequence(tr("Ctrl+Shift+Z")), QKeySequence(tr("Ctrl+Y"))}));
    redoAct->setIconText(tr("Redo"));
    addActions({undoAct, redoAct});
    QAction* deleteAct = action(tr("&Delete"), "action.delete", QKeySequence::Delete);
    connect(deleteAct, &QAction::triggered, this, [this] { deleteSelection(); });
    QAction* duplicateAct = action(tr("D&uplicate"), "action.duplicate", QKeySequence(tr("Ctrl+D")));
    connect(duplicateAct, &QAction::triggered, this, [this] { duplicateSelection(); });
    QAction* renameAct = action(tr("Re&name"), "action.rename", QKeySequence(Qt::Key_F2));
    connect(renameAct, &QAction::triggered, this, [this] {
        if (tree_->currentIndex().isValid()) tree_->edit(tree_->currentIndex().siblingAtColumn(0));
    });
    edit->addActions({undoAct, redoAct});
    edit->addSeparator();
    edit->addActions({deleteAct, duplicateAct, renameAct});

    // Add (primitives and operations), also on the feature toolbar and the tree's context menu.
    QMenu* add = menuBar()->addMenu(tr("&Add"));
    QMenu* group = new QMenu(tr("&Group Selection Under"), this);
    std::vector<QAction*> primitiveActions, operationActions;
    for (NodeType t : nodeTypesWhere(true)) {
        QAction* a = action(nodeTypeLabel(t), objectNameFor("action.add.", t));
        connect(a, &QAction::triggered, this, [this, t] { addFeature(t); });
        primitiveActions.push_back(a);
        add->addAction(a);
    }
    add->addSeparator();
    for (NodeType t : nodeTypesWhere(false)) {
        QAction* a = action(nodeTypeLabel(t), objectNameFor("action.add.", t));
        connect(a, &QAction::triggered, this, [this, t] { addFeature(t); });
        operationActions.push_back(a);
        add->addAction(a);
        QAction* g = action(nodeTypeLabel(t), objectNameFor("action.group.", t));
        connect(g, &QAction::triggered, this, [this, t] { groupSelection(t); });
        group->addAction(g);
    }
    add->addSeparator();
    add->addMenu(group);
    QAction* addMeshAct = action(tr("Reference &Mesh…"), "action.addMesh");
    connect(addMeshAct, &QAction::triggered, this, [this] {
        const QStringList files = QFileDialog::getOpenFileNames(this, tr("Add reference meshes"), {},
                                                                tr("Meshes (*.stl *.obj *.ply *.off)"));
        addMeshFiles(files);
    });
    add->addAction(addMeshAct);

    // View
    QMenu* view = menuBar()->addMenu(tr("&View"));
    for (const auto& [name, label, key] :
         {std::tuple{"iso", tr("&Isometric"), QKeySequence(tr("0"))}, std::tuple{"front", tr("&Front"), QKeySequence(tr("1"))},
          std::tuple{"back", tr("&Back"), QKeySequence()}, std::tuple{"left", tr("&Left"), QKeySequence()},
          std::tuple{"right", tr("&Right"), QKeySequence(tr("3"))}, std::tuple{"top", tr("&Top"), QKeySequence(tr("7"))},
          std::tuple{"bottom", tr("Botto&m"), QKeySequence()}}) {
        QAction* a = new QAction(label, this);
        a->setObjectName(QString("action.view.") + name);
        const QString n = name;
        connect(a, &QAction::triggered, this, [this, n] { viewport_->setStandardView(n); });
        view->addAction(a);
    }
    view->addSeparator();
    QAction* fitAct = action(tr("&Fit All"), "action.fitAll", QKeySequence(tr("F")));
    fitAct->setShortcutContext(Qt::WidgetWithChildrenShortcut);
    connect(fitAct, &QAction::triggered, viewport_, &qt::ViewportWidget::fitAll);
    QAction* orthoAct = action(tr("&Orthographic"), "action.orthographic", QKeySequence(tr("5")));
    orthoAct->setShortcutContext(Qt::WidgetWithChildrenShortcut);
    orthoAct->setCheckable(true);
    connect(orthoAct, &QAction::toggled, viewport_, &qt::ViewportWidget::setOrthographic);
    QAction* gridAct = action(tr("&Grid"), "action.grid");
    gridAct->setCheckable(true);
    gridAct->setChecked(true);
    connect(gridAct, &QAction::toggled, viewport_, &qt::ViewportWidget::setGridVisible);
    QAction* axesAct = action(tr("&Axes"), "action.axes");
    axesAct->setCheckable(true);
    axesAct->setChecked(true);
    connect(axesAct, &QAction::toggled, viewport_, &qt::ViewportWidget::setAxesVisible);
    QAction* exactAct = action(tr("&Exact Edges"), "action.exactEdges", QKeySequence(tr("E")));
    exactAct->setShortcutContext(Qt::WidgetWithChildrenShortcut);
    exactAct->setCheckable(true);
    exactAct->setToolTip(tr("Sharpen edges and intersections from the exact field near the surface (slower)"));
    connect(exactAct, &QAction::toggled, viewport_, &qt::ViewportWidget::setExactEdges);
    view->addActions({fitAct, orthoAct});
    view->addSeparator();
    view->addActions({gridAct, axesAct, exactAct});
    view->addSeparator();
    // Modelling only what the scene requires: tiles as fine as the camera
    // sees them, within a memory budget.
    refineForView_ = action(tr("&Refine Only What the View Needs"), "action.refineForView");
    refineForView_->setCheckable(true);
    refineForView_->setChecked(QSettings().value("refineForView", true).toBool());
    connect(refineForView_, &QAction::toggled, this, [this](bool on) {
        QSettings().setValue("refineForView", on);
        voxelizer_->setView(on ? viewport_->settledView() : std::nullopt);
    });
    QAction* budgetAct = action(tr("Voxel Memory &Budget…"), "action.memoryBudget");
    connect(budgetAct, &QAction::triggered, this, [this] {
        bool ok = false;
        const int mb = QInputDialog::getInt(this, tr("Voxel memory budget"),
                                            tr("Largest voxel memory (MB). Past it, the farthest tiles are coarsened:"),
                                            int(memoryBudgetBytes() >> 20), 16, 1 << 20, 64, &ok);
        if (!ok) return;
        QSettings().setValue("voxelBudgetMB", mb);
        voxelizer_->voxelizer().setMemoryBudget(memoryBudgetBytes());
        voxelizer_->submit(session_->document());
    });
    view->addActions({refineForView_, budgetAct});
    view->addSeparator();

    // Tools
    QMenu* tools = menuBar()->addMenu(tr("&Tools"));
    measureAction_ = action(tr("&Measure Distance"), "action.measure", QKeySequence(tr("M")));
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
    QAction* bboxAct = action(tr("&Bounding Box"), "action.boundingBox", QKeySequence(tr("B")));
    bboxAct->setToolTip(tr("The bounding box of the selection (of the part when nothing is selected), in the view "
                           "and the Measure panel"));
    connect(bboxAct, &QAction::triggered, this, [this] {
        if (auto* dock = findChild<QDockWidget*>("dock.measure")) dock->raise();
        measure_->showBoundingBox(selectedNodeIds());
    });
    QAction* clearAct = action(tr("&Clear Measurement"), "action.clearMeasurement", QKeySequence(Qt::Key_Escape));
    // Esc belongs to whatever has the focus (an editor, a dialog); the viewport passes it on (escapePressed).
    clearAct->setShortcutContext(Qt::WidgetShortcut);
    connect(viewport_, &qt::ViewportWidget::escapePressed, clearAct, &QAction::trigger);
    connect(clearAct, &QAction::triggered, this, [this] {
        // Esc in the viewport: first a gizmo drag, then a measurement, then measuring itself.
        if (move_->dragging()) viewport_->cancelGizmoDrag();
        else if (!measure_->clear() && measureAction_->isChecked()) measureAction_->setChecked(false);
    });
    tools->addActions({measureAction_, bboxAct, clearAct});

    // Toolbars
    QToolBar* fileBar = addToolBar(tr("File"));
    fileBar->setObjectName("toolbar.file");
    fileBar->addActions({newAct, openAct, saveAct, undoAct, redoAct, exportAct});
    QToolBar* viewBar = addToolBar(tr("View"));
    viewBar->setObjectName("toolbar.view");
    viewBar->addActions({fitAct, orthoAct, exactAct, measureAction_});
    // The features on a row of their own: beside the others they ran past
    // the edge of a 1280-pixel-wide window into the overflow menu.
    addToolBarBreak();
    QToolBar* featureBar = addToolBar(tr("Features"));
    featureBar->setObjectName("toolbar.features");
    for (QAction* a : primitiveActions) featureBar->addAction(a);
    featureBar->addSeparator();
    for (QAction* a : operationActions) featureBar->addAction(a);

    // The tree's context menu.
    connect(tree_, &QTreeView::customContextMenuRequested, this,
            [this, add, group, deleteAct, duplicateAct, renameAct](const QPoint& at) {
                QMenu menu(this);
                menu.addMenu(add);
                menu.addMenu(group);
                menu.addSeparator();
                menu.addActions({renameAct, duplicateAct, deleteAct});
                menu.exec(tree_->viewport()->mapToGlobal(at));
            });
}

void MainWindow::buildDocks()
{
    auto* treeDock = new QDockWidget(tr("Features"), this);
    treeDock->setObjectName("dock.features");
    treeDock->setWidget(tree_);
    addDockWidget(Qt::LeftDockWidgetArea, treeDock);

    auto* scroll = new QScrollArea(this);
    scroll->setWidget(properties_);
    scroll->setWidgetResizable(true);
    auto* propDock = new QDockWidget(tr("Properties"), this);
    propDock->setObjectName("dock.properties");
    propDock->setWidget(scroll);
    addDockWidget(Qt::RightDockWidgetArea, propDock);

    // Section view: a clipping plane across X, Y or Z at a draggable offset.
    auto* section = new QWidget(this);
    auto* sv = new QVBoxLayout(section);
    sectionOn_ = new QCheckBox(tr("Section view"), section);
    sectionOn_->setObjectName("section.enabled");
    sectionAxis_ = new QComboBox(section);
    sectionAxis_->setObjectName("section.axis");
    sectionAxis_->addItems({tr("Across X"), tr("Across Y"), tr("Across Z")});
    sectionSlider_ = new QSlider(Qt::Horizontal, section);
    sectionSlider_->setObjectName("section.slider");
    sectionSlider_->setRange(0, 1000);
    sectionSlider_->setValue(500);
    sectionOffset_ = new QuantityEdit(QuantityEdit::Unit::Millimetres, section);
    sectionOffset_->setObjectName("section.offset");
    sectionFlip_ = new QCheckBox(tr("Keep the other side"), section);
    sectionFlip_->setObjectName("section.flip");
    sv->addWidget(sectionOn_);
    sv->addWidget(sectionAxis_);
    sv->addWidget(sectionSlider_);
    sv->addWidget(sectionOffset_);
    sv->addWidget(sectionFlip_);
    sv->addStretch(1);
    // The slider spans the part's extent along the chosen axis; the typed
    // offset is the truth, and the slider follows it (a typed value is
    // never replaced by the slider's rounding, nor lost when the section is
    // turned off and on).
    auto extent = [this] {
        const Aabb b = voxelizer_->latest() ? voxelizer_->latest()->layout.bounds() : Aabb{glm::dvec3(-100), glm::dvec3(100)};
        const int a = sectionAxis_->currentIndex();
        return std::pair{b.min[a], b.max[a]};
    };
    auto sliderToOffset = [this, extent] {
        const auto [lo, hi] = extent();
        return lo + (hi - lo) * sectionSlider_->value() / 1000.0;
    };
    auto followOffset = [this, extent] {
        const auto [lo, hi] = extent();
        const double t = hi > lo ? (sectionOffset_->value() - lo) / (hi - lo) : 0.5;
        const QSignalBlocker block(sectionSlider_);
        sectionSlider_->setValue(int(std::lround(std::clamp(t, 0.0, 1.0) * 1000.0)));
    };
    connect(sectionSlider_, &QSlider::valueChanged, this, [this, sliderToOffset] {
        sectionPlaced_ = true;
        sectionOffset_->showValue(sliderToOffset());
        updateSection();
    });
    connect(sectionOffset_, &QuantityEdit::valueChanged, this, [this, followOffset] {
        sectionPlaced_ = true;
        followOffset();
        updateSection();
    });
    connect(sectionAxis_, &QComboBox::currentIndexChanged, this, [this, sliderToOffset] {
        sectionOffset_->showValue(sliderToOffset()); // the same place along the new axis
        updateSection();
    });
    connect(sectionOn_, &QCheckBox::toggled, this, [this, sliderToOffset, followOffset] {
        // The first time, through the middle of the part; after that where
        // it was left.
        if (sectionPlaced_) followOffset();
        else sectionOffset_->showValue(sliderToOffset());
        updateSection();
    });
    connect(sectionFlip_, &QCheckBox::toggled, this, &MainWindow::updateSection);
    auto* sectionDock = new QDockWidget(tr("Section"), this);
    sectionDock->setObjectName("dock.section");
    sectionDock->setWidget(section);
    addDockWidget(Qt::RightDockWidgetArea, sectionDock);

    measureLabel_ = new QLabel(this);
    measureLabel_->setObjectName("measure.result");
    measureLabel_->setWordWrap(true);
    measureLabel_->setTextInteractionFlags(Qt::TextSelectableByMouse);
    measureLabel_->setMargin(6);
    measureLabel_->setAlignment(Qt::AlignTop | Qt::AlignLeft);
    auto* measureDock = new QDockWidget(tr("Measure"), this);
    measureDock->setObjectName("dock.measure");
    measureDock->setWidget(measureLabel_);
    addDockWidget(Qt::RightDockWidgetArea, measureDock);
    // Section and measure share a tabbed area under the properties.
    tabifyDockWidget(sectionDock, measureDock);
    sectionDock->raise();
    propDock->setMinimumWidth(350);
    // The properties take most of the right side: a box's size and position
    // are twelve rows, the section's controls four.
    resizeDocks({propDock, sectionDock}, {560, 180}, Qt::Vertical);

    // The docks' toggles go in the View menu.
    for (QAction* a : menuBar()->actions())
        if (a->menu() && a->text() == tr("&View"))
            for (QDockWidget* d : {treeDock, propDock, sectionDock, measureDock}) a->menu()->addAction(d->toggleViewAction());
}

void MainWindow::buildStatusBar()
{
    voxelStatus_ = new QLabel(this);
    voxelStatus_->setObjectName("status.voxels");
    memoryStatus_ = new QLabel(this);
    memoryStatus_->setObjectName("status.memory");
    frameStatus_ = new QLabel(this);
    frameStatus_->setObjectName("status.frame");
    deviceStatus_ = new QLabel(this);
    deviceStatus_->setObjectName("status.device");
    statusBar()->addPermanentWidget(voxelStatus_);
    statusBar()->addPermanentWidget(memoryStatus_);
    statusBar()->addPermanentWidget(frameStatus_);
    statusBar()->addPermanentWidget(deviceStatus_);
    // A message (often the only word on a refused delete or drop) gets the
    // whole bar: the figures step aside while it shows, instead of cutting
    // it off mid-sentence.
    connect(statusBar(), &QStatusBar::messageChanged, this, [this](const QString& message) {
        for (QLabel* l : {voxelStatus_, memoryStatus_, frameStatus_, deviceStatus_})
            l->setVisible(message.isEmpty());
    });
}

// ---------------------------------------------------------------------------
// Document and selection

void MainWindow::onDocumentChanged()
{
    const Document& doc = session_->document();
    try {
        viewport_->setPickTape(std::make_shared<const Tape>(compileTape(doc)));
    } catch (const std::exception& e) {
        showMessage(tr("The part could not be compiled: %1").arg(QString::fromUtf8(e.what())));
    }
    voxelizer_->submit(doc);
    if (doc.meshes != loadedMeshes_) {
        std::vector<std::string> problems;
        const fs::path folder = session_->path() ? session_->path()->parent_path() : fs::current_path();
        viewport_->setMeshes(loadReferenceMeshes(doc, folder, problems));
        for (const auto& p : problems) showMessage(QString::fromStdString(p) + tr(" (left out)"), 10000);
        loadedMeshes_ = doc.meshes;
    }
    onSelectionChanged();
    updateTitle();
}

std::vector<std::string> MainWindow::selectedNodeIds() const
{
    std::vector<std::string> ids;
    for (const QModelIndex& i : tree_->selectionModel()->selectedRows(0)) ids.push_back(model_->nodeIdAt(i));
    // In tree order, so that grouping keeps the order of the siblings.
    std::vector<std::string> ordered;
    std::function<void(const Node&)> walk = [&](const Node& n) {
        if (std::find(ids.begin(), ids.end(), n.id) != ids.end()) ordered.push_back(n.id);
        for (const auto& c : n.children) walk(c);
    };
    walk(session_->document().root);
    return ordered;
}

void MainWindow::selectNodes(const std::vector<std::string>& ids)
{
    QItemSelection selection;
    QModelIndex current;
    for (const auto& id : ids) {
        const QModelIndex i = model_->indexOf(id);
        if (!i.isValid()) continue;
        selection.select(i, model_->indexOf(id, FeatureTreeModel::TypeColumn));
        current = i;
        for (QModelIndex p = i.parent(); p.isValid(); p = p.parent()) tree_->setExpanded(p, true);
    }
    tree_->selectionModel()->select(selection, QItemSelectionModel::ClearAndSelect);
    if (current.isValid()) {
        tree_->selectionModel()->setCurrentIndex(current, QItemSelectionModel::NoUpdate);
        tree_->scrollTo(current);
    }
    onSelectionChanged();
}

void MainWindow::onSelectionChanged()
{
    if (resettingTree_) return;
    const std::vector<std::string> ids = selectedNodeIds();
    properties_->setNode(ids.size() == 1 ? ids.front() : std::string());
    std::unordered_set<std::string> features;
    for (const auto& id : ids)
        if (const Node* n = session_->document().root.find(id)) collectFeatureNodes(*n, features);
    viewport_->setSelectedFeatureNodes(std::move(features));
    move_->setNode(ids.size() == 1 ? ids.front() : std::string());
    ghosts_->show(session_->document(), ids);
}

void MainWindow::onViewportClicked(const qt::ViewportPick& pick)
{
    if (measureAction_->isChecked()) {
        measure_->click(pick);
        return;
    }
    if (!pick.hit || pick.nodeId.empty()) {
        if (!(pick.modifiers & Qt::ControlModifier)) selectNodes({});
        return;
    }
    std::vector<std::string> ids;
    if (pick.modifiers & Qt::ControlModifier) ids = selectedNodeIds();
    auto it = std::find(ids.begin(), ids.end(), pick.nodeId);
    if (it != ids.end()) ids.erase(it);
    else ids.push_back(pick.nodeId);
    selectNodes(ids);
}

QString MainWindow::measureText() const { return measureLabel_->text(); }

bool MainWindow::ghostsBusy() const { return ghosts_->busy(); }

void MainWindow::updateSection()
{
    if (!sectionOn_->isChecked()) {
        viewport_->setSection(Section{});
        return;
    }
    viewport_->setSection(Section::alongAxis(sectionAxis_->currentIndex(), sectionOffset_->value(), sectionFlip_->isChecked()));
}

// ---------------------------------------------------------------------------
// Structural edits

bool MainWindow::addFeature(NodeType type)
{
    // Where it goes and what it starts with: edit::addFeature (AddFeature.hpp).
    const std::vector<std::string> selection = selectedNodeIds();
    std::string id;
    QString error;
    const bool ok = session_->apply(tr("Add %1").arg(nodeTypeLabel(type)),
                                    [&](Document& d) { id = edit::addFeature(d, type, selection); }, &error);
    if (!ok) {
        showMessage(tr("Cannot add the %1: %2").arg(nodeTypeLabel(type).toLower(), error));
        return false;
    }
    selectNodes({id});
    return true;
}

bool MainWindow::groupSelection(NodeType type)
{
    const std::vector<std::string> ids = selectedNodeIds();
    if (ids.empty()) {
        showMessage(tr("Select the features to group first."));
        return false;
    }
    const std::string id = edit::uniqueId(session_->document(), std::string(nodeTypeName(type)));
    QString error;
    const bool ok = session_->apply(tr("Group under %1").arg(nodeTypeLabel(type)),
                                    [&](Document& d) { edit::wrapNodes(d, ids, makeNode(type, id)); }, &error);
    if (!ok) {
        showMessage(tr("Cannot group: %1").arg(error));
        return false;
    }
    selectNodes({id});
    return true;
}

bool MainWindow::deleteSelection()
{
    const std::vector<std::string> ids = selectedNodeIds();
    if (ids.empty()) return false;
    QString error;
    const Node* only = ids.size() == 1 ? session_->document().root.find(ids.front()) : nullptr;
    const bool ok = session_->apply(only ? tr("Delete %1").arg(featureName(*only))
                                         : tr("Delete %1 features").arg(ids.size()),
                                    [&](Document& d) {
                                        for (const auto& id : ids)
                                            if (d.root.find(id)) edit::removeNode(d, id);
                                    },
                                    &error);
    if (!ok) showMessage(tr("Cannot delete: %1").arg(error));
    return ok;
}

bool MainWindow::duplicateSelection()
{
    const std::vector<std::string> ids = selectedNodeIds();
    if (ids.empty()) return false;
    std::vector<std::string> copies;
    QString error;
    const bool ok = session_->apply(tr("Duplicate"),
                                    [&](Document& d) {
                                        copies.clear();
                                        for (const auto& id : ids) copies.push_back(edit::duplicateNode(d, id));
                                    },
                                    &error);
    if (!ok) {
        showMessage(tr("Cannot duplicate: %1").arg(error));
        return false;
    }
    selectNodes(copies);
    return true;
}

void MainWindow::addMeshFiles(const QStringList& files)
{
    if (files.isEmpty()) return;
    QString error;
    const std::optional<fs::path> docFolder = session_->path() ? std::optional(session_->path()->parent_path()) : std::nullopt;
    const bool ok = session_->apply(tr("Add reference mesh"),
                                    [&](Document& d) {
                                        for (const QString& f : files) {
                                            // Check it loads first: a broken mesh is named, not added.
                                            loadTriangleMesh(f.toStdString());
                                            MeshReference m;
                                            std::string stem = QFileInfo(f).completeBaseName().toStdString();
                                            std::string id = stem.empty() ? "mesh" : stem;
                                            for (int k = 2; std::any_of(d.meshes.begin(), d.meshes.end(),
                                                                        [&](const MeshReference& r) { return r.id == id; });
                                                 ++k)
                                                id = stem + "-" + std::to_string(k);
                                            m.id = id;
                                            fs::path p = fs::absolute(f.toStdString());
                                            if (docFolder) p = p.lexically_relative(fs::absolute(*docFolder));
                                            m.path = p.string();
                                            d.meshes.push_back(m);
                                        }
                                    },
                                    &error);
    if (!ok) showMessage(tr("Cannot add the mesh: %1").arg(error));
}

// ---------------------------------------------------------------------------
// Files

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
    if (!maybeSave()) return false;
    try {
        Document doc = Document::load(file);
        // A bundled example opens as an untitled copy: Save asks where to
        // keep it instead of overwriting the installed file.
        const bool example = isBundledExample(file);
        session_->reset(std::move(doc), example ? std::nullopt : std::optional<fs::path>(file));
        untitledStem_ = example ? QString::fromStdString(file.stem().string()) : QStringLiteral("part");
        recovery_->clearAutosave();
        if (!example) addRecentFile(file);
        showMessage(example ? tr("Opened a copy of the example %1: Save asks where to keep it.")
                                  .arg(QString::fromStdString(file.filename().string()))
                            : tr("Opened %1").arg(QString::fromStdString(file.string())));
        tree_->expandToDepth(1);
        QTimer::singleShot(0, viewport_, [this] { viewport_->setStandardView("iso"); });
        return true;
    } catch (const DocumentError& e) {
        showMessage(QString::fromUtf8(e.what()), 0);
        reportError(tr("Cannot open"), QString::fromUtf8(e.what()));
        return false;
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
        const QString suggested = session_->path() ? QString::fromStdString(session_->path()->string())
                                                   : QDir::homePath() + "/" + untitledStem_ + ".kerf";
        const QString f = askFile(true, suggested);
        if (f.isEmpty()) return false;
        target = f.toStdString();
    }
    try {
        session_->saveAs(target);
        recovery_->clearAutosave();
        autosavedRevision_ = session_->revision();
        addRecentFile(target);
        showMessage(tr("Saved %1").arg(QString::fromStdString(target.string())));
        return true;
    } catch (const std::exception& e) {
        showMessage(tr("Not saved: %1").arg(QString::fromUtf8(e.what())), 0);
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

void MainWindow::addRecentFile(const fs::path& file)
{
    QSettings settings;
    QStringList list = settings.value("recentFiles").toStringList();
    const QString f = QString::fromStdString(fs::absolute(file).string());
    list.removeAll(f);
    list.prepend(f);
    while (list.size() > kMaxRecentFiles) list.removeLast();
    settings.setValue("recentFiles", list);
    rebuildRecentMenu();
}

void MainWindow::rebuildRecentMenu()
{
    recentMenu_->clear();
    const QStringList list = QSettings().value("recentFiles").toStringList();
    for (const QString& f : list) {
        QAction* a = recentMenu_->addAction(QFileInfo(f).fileName());
        a->setToolTip(f);
        connect(a, &QAction::triggered, this, [this, f] { openFile(f.toStdString()); });
    }
    recentMenu_->setEnabled(!list.isEmpty());
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

// ---------------------------------------------------------------------------
// Title and status

void MainWindow::updateTitle()
{
    setWindowTitle(tr("%1[*] — Kerf").arg(session_->displayName()));
    setWindowModified(session_->isModified());
}

void MainWindow::showMessage(const QString& text, int timeoutMs)
{
    lastMessage_ = text;
    statusBar()->showMessage(text, timeoutMs);
}

void MainWindow::updateStatus()
{
    const VoxelizerProgress p = voxelizer_->progress();
    const auto snap = voxelizer_->latest();
    const qt::ViewportStatus v = viewport_->status();
    if (p.busy) {
        voxelStatus_->setText(tr("Voxelizing: %1 %2 of %3 tiles (depth %4 of %5)")
                                  .arg(p.coarsePass ? tr("coarse preview") : tr("refining"))
                                  .arg(p.tilesBuilt)
                                  .arg(p.tilesToBuild)
                                  .arg(p.levels)
                                  .arg(p.targetLevels));
    } else if (snap) {
        const VoxelizerStats s = voxelizer_->lastStats();
        voxelStatus_->setText(tr("Voxels: %L1 tiles, depth %2, %3 rebuilt; %4 mm")
                                  .arg(snap->layout.tileCount())
                                  .arg(snap->layout.levels)
                                  .arg(s.dirtyTiles)
                                  .arg(snap->layout.voxelSize, 0, 'g', 3));
    }
    QString memory = tr("%1: %2 MB%3")
                         .arg(v.vulkan ? tr("GPU") : tr("Voxels"))
                         .arg(double(v.voxelBytes) / 1e6, 0, 'f', 1)
                         .arg(v.streaming ? tr(" (streaming)") : QString());
    if (snap && snap->coarsenedForBudget > 0)
        memory += tr(" — budget of %1 MB reached: %2 distant tiles coarsened")
                      .arg(memoryBudgetBytes() >> 20)
                      .arg(snap->coarsenedForBudget);
    if (snap && snap->hiddenTiles > 0)
        memory += snap->hiddenTiles == 1 ? tr(" — 1 hidden tile kept coarse")
                                         : tr(" — %1 hidden tiles kept coarse").arg(snap->hiddenTiles);
    memoryStatus_->setText(memory);
    memoryStatus_->setStyleSheet(snap && snap->coarsenedForBudget > 0 ? QStringLiteral("color: #b35900;") : QString());
    frameStatus_->setText(v.traceMs >= 0.0 ? tr("Frame %1 ms, trace %2 ms").arg(v.frameMs, 0, 'f', 1).arg(v.traceMs, 0, 'f', 1)
                                           : tr("Frame %1 ms").arg(v.frameMs, 0, 'f', 1));
    deviceStatus_->setText(v.device);
    deviceStatus_->setToolTip(v.fallbackReason);
}

} // namespace kerf::ui
