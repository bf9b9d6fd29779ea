#pragma once
// Completes the document's parameter names while an expression is typed:
// the word under the cursor ("=thi" offers "thickness"), not the whole
// text, so it works in the middle of "depth - 2*thi". For the Parameters
// panel's expressions and the property fields' "=...", which also offer the
// features' numbers ("=pan" offers "panel.size[2]": a newcomer could not
// refer to a board's thickness without knowing its id, which the
// application did not show).

#include <QObject>
#include <QStringList>

#include <functional>

class QCompleter;
class QLineEdit;
class QStringListModel;

namespace kerf {
struct Document;
}

namespace kerf::ui {

/// The document's parameter names, in its order.
QStringList parameterNames(const Document& doc);

/// The parameter names, then every feature's numbers an expression can refer to.
QStringList parameterAndFeatureNames(const Document& doc);

class NameCompleter : public QObject {
    Q_OBJECT
public:
    /// `names` is asked each time (the parameters change); with
    /// `onlyAfterEquals` it completes only text that starts with '='.
    NameCompleter(QLineEdit* edit, std::function<QStringList()> names, bool onlyAfterEquals);

    QCompleter* completer() const { return completer_; }

protected:
    bool eventFilter(QObject* watched, QEvent* event) override;

private:
    void offer();
    void insert(const QString& name);
    /// Where the word under the cursor starts (the cursor itself when there is none).
    int wordStart() const;

    QLineEdit* edit_;
    std::function<QStringList()> names_;
    bool onlyAfterEquals_;
    QCompleter* completer_;
    QStringListModel* model_;
};

} // namespace kerf::ui
