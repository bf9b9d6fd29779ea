// The Edit and Add menus' commands: add a feature, group, delete,
// duplicate, add reference meshes. Each is one undoable step through the
// DocumentSession; where a feature goes and what it starts with, how a
// selection is grouped and how a mesh is referenced are the core's rules
// (AddFeature.hpp, DocumentEdits.hpp).

#include "MainWindow.hpp"
#include "NodeText.hpp"
#include "kerf/document/AddFeature.hpp"
#include "kerf/document/DocumentEdits.hpp"
#include "kerf/document/NodeTypes.hpp"
#include "kerf/viewport/ReferenceMesh.hpp"

namespace kerf::ui {

namespace fs = std::filesystem;

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
    const std::optional<fs::path> folder = session_->path() ? std::optional(session_->path()->parent_path()) : std::nullopt;
    const bool ok = session_->apply(tr("Add reference mesh"),
                                    [&](Document& d) {
                                        for (const QString& f : files) {
                                            // Check it loads first: a broken mesh is named, not added.
                                            loadTriangleMesh(f.toStdString());
                                            edit::addMeshReference(d, f.toStdString(), folder);
                                        }
                                    },
                                    &error);
    if (!ok) showMessage(tr("Cannot add the mesh: %1").arg(error));
}

} // namespace kerf::ui
