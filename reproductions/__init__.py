"""resal: a reproduction of H. Résal (1883), "Commentaire à la théorie mathématique du jeu de billard"."""

__version__ = "0.1.0"
