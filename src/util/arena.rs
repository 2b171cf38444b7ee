//! A slot arena with a free list and generations (Box2D v3's id pool).
//!
//! Insertion reuses the most recently freed slot (LIFO), so indices stay dense and the
//! same sequence of operations always yields the same ids: determinism needs no more.
//! Iteration is in slot order, never in hash order.

#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
struct Slot<T> {
    generation: u32,
    value: Option<T>,
}

#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct Arena<T> {
    slots: Vec<Slot<T>>,
    free: Vec<u32>,
    len: usize,
}

impl<T> Default for Arena<T> {
    fn default() -> Self {
        Self {
            slots: Vec::new(),
            free: Vec::new(),
            len: 0,
        }
    }
}

impl<T> Arena<T> {
    /// Inserts and returns `(index, generation)`. O(1) amortised.
    pub fn insert(&mut self, value: T) -> (u32, u32) {
        self.len += 1;
        if let Some(i) = self.free.pop() {
            let slot = &mut self.slots[i as usize];
            debug_assert!(slot.value.is_none());
            slot.value = Some(value);
            (i, slot.generation)
        } else {
            let i = self.slots.len() as u32;
            self.slots.push(Slot {
                generation: 0,
                value: Some(value),
            });
            (i, 0)
        }
    }

    /// Makes room for `additional` more values without reallocating (the free slots
    /// count). O(1) amortised, O(slots) when it grows.
    pub fn reserve(&mut self, additional: usize) {
        self.slots
            .reserve(additional.saturating_sub(self.free.len()));
    }

    /// Removes the value at `(index, generation)`; the slot's generation is bumped.
    pub fn remove(&mut self, index: u32, generation: u32) -> Option<T> {
        let slot = self.slots.get_mut(index as usize)?;
        if slot.generation != generation || slot.value.is_none() {
            return None;
        }
        slot.generation = slot.generation.wrapping_add(1);
        self.free.push(index);
        self.len -= 1;
        slot.value.take()
    }

    #[inline]
    pub fn get(&self, index: u32, generation: u32) -> Option<&T> {
        let slot = self.slots.get(index as usize)?;
        if slot.generation == generation {
            slot.value.as_ref()
        } else {
            None
        }
    }

    #[inline]
    pub fn get_mut(&mut self, index: u32, generation: u32) -> Option<&mut T> {
        let slot = self.slots.get_mut(index as usize)?;
        if slot.generation == generation {
            slot.value.as_mut()
        } else {
            None
        }
    }

    /// The live value at `index`, whatever its generation.
    #[inline]
    pub fn get_by_index(&self, index: u32) -> Option<(u32, &T)> {
        let slot = self.slots.get(index as usize)?;
        slot.value.as_ref().map(|v| (slot.generation, v))
    }

    #[inline]
    pub fn len(&self) -> usize {
        self.len
    }

    /// Number of slots, live or free.
    #[inline]
    pub fn slot_count(&self) -> usize {
        self.slots.len()
    }

    /// Checks the free list against the slots (for a deserialised arena): every free
    /// index names an empty slot, once, every empty slot is free, and `len` counts the
    /// live ones. Insertion indexes the slot a free index names, so a snapshot must
    /// pass this before it is used. O(slots).
    #[cfg(feature = "serde")]
    pub fn check(&self) -> Result<(), String> {
        let mut free = vec![false; self.slots.len()];
        for &i in &self.free {
            match self.slots.get(i as usize) {
                None => return Err(format!("free slot {i} is out of range")),
                Some(s) if s.value.is_some() => return Err(format!("free slot {i} is occupied")),
                Some(_) if free[i as usize] => return Err(format!("slot {i} is free twice")),
                Some(_) => free[i as usize] = true,
            }
        }
        let live = self.slots.iter().filter(|s| s.value.is_some()).count();
        if live + self.free.len() != self.slots.len() {
            return Err(format!(
                "{} slots, {live} live and {} free",
                self.slots.len(),
                self.free.len()
            ));
        }
        if live != self.len {
            return Err(format!("{live} live slots but a count of {}", self.len));
        }
        Ok(())
    }

    /// Live values in slot order, with `(index, generation)`.
    pub fn iter(&self) -> impl Iterator<Item = (u32, u32, &T)> + '_ {
        self.slots
            .iter()
            .enumerate()
            .filter_map(|(i, s)| s.value.as_ref().map(|v| (i as u32, s.generation, v)))
    }

    /// Live values in slot order, mutably. O(slots).
    pub fn values_mut(&mut self) -> impl Iterator<Item = &mut T> + '_ {
        self.slots.iter_mut().filter_map(|s| s.value.as_mut())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reuse_bumps_generation() {
        let mut a = Arena::default();
        let (i, g) = a.insert("x");
        assert_eq!(a.remove(i, g), Some("x"));
        assert_eq!(a.remove(i, g), None, "double remove is refused");
        let (j, h) = a.insert("y");
        assert_eq!(i, j);
        assert_ne!(g, h);
        assert_eq!(a.get(i, g), None, "stale generation");
        assert_eq!(a.get(j, h), Some(&"y"));
        assert_eq!(a.len(), 1);
    }

    #[test]
    fn reserve_makes_room_and_changes_no_id() {
        let mut a = Arena::default();
        let (i, g) = a.insert(1);
        a.remove(i, g);
        a.reserve(100);
        assert!(
            a.slots.capacity() >= 100,
            "the free slot counts, the rest is new"
        );
        let mut b = Arena::default();
        let (i2, g2) = b.insert(1);
        b.remove(i2, g2);
        // The same operations give the same ids with or without the reservation.
        for k in 0..100 {
            assert_eq!(a.insert(k), b.insert(k));
        }
        assert_eq!(a.len(), 100);
    }

    #[cfg(feature = "serde")]
    #[test]
    fn check_refuses_a_broken_free_list() {
        let mut a = Arena::default();
        let (i, g) = a.insert(1);
        a.insert(2);
        a.remove(i, g);
        assert_eq!(a.check(), Ok(()));
        let mut b = a.clone();
        b.free.push(7);
        assert!(b.check().unwrap_err().contains("out of range"));
        let mut b = a.clone();
        b.free = vec![1];
        assert!(b.check().unwrap_err().contains("occupied"));
        let mut b = a.clone();
        b.free.push(0);
        assert!(b.check().unwrap_err().contains("twice"));
        let mut b = a.clone();
        b.free.clear();
        assert!(b.check().is_err(), "an empty slot that is not free");
        let mut b = a.clone();
        b.len = 2;
        assert!(b.check().unwrap_err().contains("count"));
    }
}
