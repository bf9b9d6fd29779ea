#pragma once
// The feature tree as a Qt item model over the session's document: one row
// per node (name, type), a check box for visibility, the node's colour as a
// swatch, names editable in place, rows dragged to reorder or regroup. Every
// change goes through the session as an undoable edit.
//
// The model mirrors the document after every change (a reset); views keep
// their expanded rows and selection by node id across it.

#include "DocumentSession.hpp"

#include <QAbstractItemModel>

#include <functional>
#include <string>
#include <unordered_set>
#include <vector>

namespace kerf::ui {

class FeatureTreeModel : public QAbstractItemModel {
    Q_OBJECT
public:
    static constexpr const char* kMimeType = "application/x-kerf-node-ids";
    enum Column { NameColumn = 0, TypeColumn = 1, ColumnCount = 2 };
    static constexpr int NodeIdRole = Qt::UserRole + 1;

    explicit FeatureTreeModel(DocumentSession* session, QObject* parent = nullptr);

    QModelIndex indexOf(const std::string& nodeId, int column = 0) const;
    std::string nodeIdAt(const QModelIndex& index) const;

    QModelIndex index(int row, int column, const QModelIndex& parent = {}) const override;
    QModelIndex parent(const QModelIndex& child) const override;
    int rowCount(const QModelIndex& parent = {}) const override;
    int columnCount(const QModelIndex& parent = {}) const override;
    QVariant data(const QModelIndex& index, int role = Qt::DisplayRole) const override;
    QVariant headerData(int section, Qt::Orientation orientation, int role) const override;
    Qt::ItemFlags flags(const QModelIndex& index) const override;
    bool setData(const QModelIndex& index, const QVariant& value, int role) override;

    Qt::DropActions supportedDropActions() const override { return Qt::MoveAction; }
    QStringList mimeTypes() const override { return {kMimeType}; }
    QMimeData* mimeData(const QModelIndexList& indexes) const override;
    bool canDropMimeData(const QMimeData* data, Qt::DropAction action, int row, int column,
                         const QModelIndex& parent) const override;
    bool dropMimeData(const QMimeData* data, Qt::DropAction action, int row, int column,
                      const QModelIndex& parent) override;

    /// Asked (a question, true to go on) before a drop that changes which
    /// child of a difference is its base. None: such drops go ahead.
    void setConfirm(std::function<bool(const QString& question)> confirm) { confirm_ = std::move(confirm); }

signals:
    /// An edit made through the model was refused (the reason, in a sentence).
    void editRefused(const QString& reason);

private:
    std::function<bool(const QString&)> confirm_;
    // A flattened copy of the tree: items refer to each other by index.
    struct Item {
        std::string id;
        int parent = -1; // -1: the root's row
        int row = 0;
        std::vector<int> children;
    };
    std::vector<Item> flatten() const;
    static void add(std::vector<Item>& items, const Node& n, int parent, int row);
    void emitChangedBelow(const QModelIndex& parent);
    const Node* nodeOf(const QModelIndex& index) const;

    DocumentSession* session_;
    std::vector<Item> items_; // items_[0] is the document's root
    // Tools that cut nothing (toolsCuttingNothing), marked in the Type column.
    std::unordered_set<std::string> cutNothing_;
};

} // namespace kerf::ui
