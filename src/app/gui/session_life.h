#pragma once
// The questions a session window asks before it ends a session (issue 15): quitting or leaving while hosting with
// people in the session, and opening another mesh while hosting or joined. Text and a default QMessageBox; the
// window takes a SessionAsker so that tests answer without a modal box (MainWindow::setSessionAsker()).

#include <QString>

#include <functional>

class QWidget;

namespace sc::app {

enum class SessionAnswer { End, Rehost, Cancel };

/// One question: the text and the labels of its buttons (an empty rehostLabel: no re-host button).
struct SessionQuestion {
  QString title;
  QString text;
  QString endLabel;
  QString rehostLabel;
};

/// Answers a question (the default: askInMessageBox()).
using SessionAsker = std::function<SessionAnswer(const SessionQuestion&)>;

/// "N people are in this session. End it for everyone?" with End session / Cancel. @p others ≥ 1.
SessionQuestion endSessionQuestion(int others);
/// Opening `opening` (a file name) while hosting `hosted`: End the session and open / Host `opening` instead /
/// Cancel.
SessionQuestion openWhileHostingQuestion(const QString& hosted, const QString& opening);
/// Opening `opening` while joined to `session` ("host:port"): Leave the session and open / Cancel.
SessionQuestion openWhileJoinedQuestion(const QString& session, const QString& opening);

/// A modal QMessageBox (objectName "sessionQuestionBox", plain text) with the question's buttons; Cancel when
/// closed otherwise.
SessionAnswer askInMessageBox(QWidget* parent, const SessionQuestion& question);

}  // namespace sc::app
