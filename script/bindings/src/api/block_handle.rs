//! The script's `Block`: a kernel block behind a handle, so that the block a Block method
//! returns is the block it was called on and a chain of edits on a variable edits that
//! variable (`b.subdivide("+z", 2, 2).sharp_all();` leaves `b` subdivided and sharp).
//!
//! Every other copy is a copy: `Clone` copies the block itself, and Rhai clones a value
//! wherever a script copies one (`let c = b;`, an argument, `[b, b]`, an array's element read
//! into a variable, a `for` loop's variable), so those blocks change independently. Only
//! [`Block::same`], which the methods return, shares the block.

use std::cell::{Ref, RefCell, RefMut};
use std::fmt;
use std::rc::Rc;

use blocksmith_kernel::blocks::Block as KernelBlock;

/// A block as scripts hold it (script type `Block`).
pub struct Block {
    inner: Rc<RefCell<KernelBlock>>,
}

impl Block {
    /// A new block holding `b`.
    #[must_use]
    pub fn new(b: KernelBlock) -> Block {
        Block { inner: Rc::new(RefCell::new(b)) }
    }

    /// This very block: a second handle whose edits reach this one (what a Block method
    /// returns, for the next call of a chain).
    #[must_use]
    pub fn same(&self) -> Block {
        Block { inner: Rc::clone(&self.inner) }
    }

    /// The kernel block, to read.
    ///
    /// # Panics
    /// Never in practice: no block method keeps the block borrowed while a script runs.
    #[must_use]
    pub fn read(&self) -> Ref<'_, KernelBlock> {
        self.inner.borrow()
    }

    /// The kernel block, to change.
    ///
    /// # Panics
    /// As [`Block::read`].
    #[must_use]
    pub fn write(&self) -> RefMut<'_, KernelBlock> {
        self.inner.borrow_mut()
    }

    /// A copy of the kernel block as it is now.
    #[must_use]
    pub fn kernel_copy(&self) -> KernelBlock {
        self.read().clone()
    }
}

impl Clone for Block {
    /// A copy of the block: its later edits do not reach this one, nor this one's it.
    fn clone(&self) -> Block {
        Block::new(self.kernel_copy())
    }
}

impl fmt::Debug for Block {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.read().fmt(f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use blocksmith_kernel::Vec3;

    #[test]
    fn a_clone_is_independent_and_the_same_handle_is_not() {
        let a = Block::new(KernelBlock::from_bounds(Vec3::ZERO, Vec3::ONE).unwrap());
        let copy = a.clone();
        let same = a.same();
        same.write().set_group(4);
        assert_eq!(a.read().group(), 4);
        assert_eq!(copy.read().group(), 0);
        copy.write().set_group(7);
        assert_eq!(a.read().group(), 4);
    }
}
