#pragma once
// The property editor: typed fields for the selected node (its name,
// visibility, colour, transform and the parameters of its type), in
// millimetres and degrees, taking expressions. A value is committed as an
// undoable edit when it is entered (Enter, leaving the field, an arrow
// step, the wheel); steps of one field in a row merge into one undo step.
// A value the document refuses (a negative radius, a round larger than the
// box) is not applied: the reason appears under the field and the field
// shows the document's value again.
//
// Fields are named for tests and scripts: objectName "field.<spec name>"
// ("field.radius", "field.size.x", "field.translate.z", "field.name").

#include "DocumentSession.hpp"

#include "kerf/document/NodeTypes.hpp"

#include <QWidget>

#include <functional>
#include <string>
#include <vector>

class QFormLayout;
class QLabel;
class QLineEdit;
class QCheckBox;
class QTableWidget;
class QPushButton;

namespace kerf::ui {

class QuantityEdit;

class PropertyEditor : public QWidget {
    Q_OBJECT
public:
    explicit PropertyEditor(DocumentSession* session, QWidget* parent = nullptr);

    /// Shows the node with this id (none: an empty editor).
    void setNode(const std::string& nodeId);
    /// Shows what the selection is: its one node, the part when it is
    /// empty, or how many are selected (a newcomer with three rows selected
    /// read "Nothing selected — the part").
    void setSelection(const std::vector<std::string>& nodeIds);
    const std::string& nodeId() const { return nodeId_; }
    /// The message shown under a field ("" when none), by spec name.
    QString errorFor(const QString& field) const;
    /// The expression that drives a field ("" when a plain number), by spec name.
    QString expressionFor(const QString& field) const;
    /// A field's spec name as a path of the document's expressions ("size.x" -> "size[0]").
    static QString expressionPath(const QString& key);

private:
    struct Field {
        QString key;   // spec name: "radius", "size.x"
        QString label; // as the row shows it: "Bottom radius", "Size X"
        QuantityEdit* edit = nullptr;
        QLabel* error = nullptr;
        std::function<double(const Node&)> get;
        std::function<void(Node&, double)> set;
    };
    void rebuild();
    void refresh();
    void addQuantity(const QString& label, const QString& key, int unit, std::function<double(const Node&)> get,
                     std::function<void(Node&, double)> set, int decimals = 6);
    void addVector(const QString& label, const QString& key, int unit, std::function<glm::dvec3(const Node&)> get,
                   std::function<void(Node&, int, double)> set, int decimals = 6);
    void commit(std::size_t index, double value, bool step);
    /// "=..." typed into a field: the field is driven by that expression from now on.
    void commitExpression(std::size_t index, const QString& expression);
    bool applyToNode(const QString& text, const std::function<void(Node&)>& change, QLabel* error,
                     const QString& mergeKey = {});
    void showError(QLabel* error, const QString& message);
    void addProfileTable(const FieldSpec& field);
    /// "Along X", "Along Y", "Along Z" under a direction's fields.
    void addAxisButtons(const QString& label, const QString& key, const FieldSpec& field);
    void addPartSettings();
    void commitProfile();

    DocumentSession* session_;
    std::string nodeId_;
    std::size_t selected_ = 0; // more than one: how many (nodeId_ is then empty)
    NodeType shownType_ = NodeType::Union;
    QFormLayout* form_ = nullptr;
    QLabel* title_ = nullptr;
    QLineEdit* name_ = nullptr;
    QCheckBox* visible_ = nullptr;
    QPushButton* color_ = nullptr;
    QLabel* generalError_ = nullptr;
    QTableWidget* profile_ = nullptr;
    const FieldSpec* profileField_ = nullptr; // the table's field in the node type table
    QLabel* profileError_ = nullptr;
    QuantityEdit* partFeatureSize_ = nullptr; // nothing selected: the document's feature size
    QLabel* partError_ = nullptr;
    std::vector<Field> fields_;
    bool refreshing_ = false;
};

} // namespace kerf::ui
