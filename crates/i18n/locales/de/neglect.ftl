# Der Hinweis vor einer Übung, auf der vernachlässigten Seite.
neglect-look-here = Schauen Sie hierher.
